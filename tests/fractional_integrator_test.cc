// The fractional integrator of eq. 14 and its realisations
// (controllers/fractional_integrator.h): Oustaloup's, and eq. 15 as printed
// (controllers/paper_eq15.h); the zero-order-hold discretisation, the
// clamp, and bad configurations.
//
// Independent references used below:
//  - a fine RK4 integration of the continuous Oustaloup realisation (for
//    the exactness of the zero-order-hold discretisation);
//  - closed forms (ZOH of 1/s, eq. 15's step response by partial fractions);
//  - docs/VALIDATION.md, "The paper's numbers, computed independently"
//    (numpy/scipy/mpmath, rounded).
#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/test_util.h"
#include "tests/controller_test_util.h"
#include "controllers/first_order_sections.h"
#include "controllers/fractional_integrator.h"
#include "sim/linear/oustaloup.h"
#include "sim/linear/state_space.h"
#include "controllers/paper_eq15.h"
#include "sim/base/numbers.h"

namespace ipmc {
namespace {

using ::ipmc::testing::ExpectThrowMentioning;
using ::ipmc::testing::Db;
using ::ipmc::testing::Deg;
using ::ipmc::testing::WideBandIntegrator;
using Complex = std::complex<double>;

TEST(FractionalIntegratorTest, DefaultsAreEquations14And15) {
  const FractionalIntegrator::Config config;
  EXPECT_EQ(config.gain, 15.62);
  EXPECT_EQ(config.order, 0.62);
  EXPECT_EQ(config.oustaloup_n, 4);
  EXPECT_EQ(config.w_low_rad_s, 1e-3);
  EXPECT_EQ(config.w_high_rad_s, 1e2);
  EXPECT_EQ(config.sample_period_s, 1e-3);
  EXPECT_EQ(config.v_max, 6.0);
  // Eq. 14 through Oustaloup unless eq. 15 is asked for, so results made
  // before the eq. 15 realisation existed do not change.
  EXPECT_EQ(config.realisation, FractionalRealisation::kOustaloup);
}

TEST(FractionalIntegratorTest, ExactResponseAtFiveRadPerSecond) {
  // docs/VALIDATION.md: 15.21 dB, -55.80 deg (measured 15.2064 dB, -55.8 deg: the
  // phase is exactly -0.62 * 90 deg).
  const FractionalIntegrator integrator(FractionalIntegrator::Config{});
  const Complex h = integrator.EvaluateExact({0.0, 5.0});
  EXPECT_NEAR(Db(h), 15.21, 0.01);
  EXPECT_NEAR(Deg(h), -55.80, 1e-12);
}

TEST(FractionalIntegratorTest, RealisationAgainstEquation15AndExact) {
  // Eq. 15 as printed (controllers/paper_eq15.h).
  const auto eq15 = [](double w) { return Eq15Evaluate({0.0, w}); };
  // docs/VALIDATION.md: eq. 15 is the N-pairs approximation of order -0.6248 to
  // 0.05 % in its coefficients; with -0.62 it differs by 3 % / 0.27 dB.
  // Measured over [1e-3, 1e3] rad/s: order 0.6248, max |ratio - 1| 5.5e-4
  // (tolerance 1e-3); order 0.62, max 0.274 dB and 0.448 deg (tolerances
  // 0.3 dB, 0.5 deg).
  FractionalIntegrator::Config config;
  config.order = 0.6248;
  const FractionalIntegrator printed(config);
  const FractionalIntegrator paper(FractionalIntegrator::Config{});
  double worst_ratio = 0, worst_dB = 0, worst_deg = 0;
  for (double w = 1e-3; w <= 1e3; w *= 1.1) {
    worst_ratio = std::max(
        worst_ratio, std::abs(printed.Evaluate({0.0, w}) / eq15(w) - 1.0));
    const Complex ratio = paper.Evaluate({0.0, w}) / eq15(w);
    worst_dB = std::max(worst_dB, std::abs(Db(ratio)));
    worst_deg = std::max(worst_deg, std::abs(Deg(ratio)));
  }
  EXPECT_LT(worst_ratio, 1e-3);
  EXPECT_LT(worst_dB, 0.3);
  EXPECT_LT(worst_deg, 0.5);

  // The wide-band realisation follows K (j w)^-0.62 closely in the
  // decades that matter for the loop. Measured on [1e-2, 1e2] rad/s:
  // 0.0031 dB, 0.055 deg; tolerances 0.03 dB and 0.5 deg.
  const FractionalIntegrator wide(WideBandIntegrator(1e-3));
  double wide_dB = 0, wide_deg = 0;
  for (double w = 1e-2; w <= 1e2; w *= 1.05) {
    const Complex ratio =
        wide.Evaluate({0.0, w}) / wide.EvaluateExact({0.0, w});
    wide_dB = std::max(wide_dB, std::abs(Db(ratio)));
    wide_deg = std::max(wide_deg, std::abs(Deg(ratio)));
  }
  EXPECT_LT(wide_dB, 0.03);
  EXPECT_LT(wide_deg, 0.5);
}

// Step response of the continuous block (a, b, c, d) at t = k T by RK4
// with 20 sub-steps per T.
std::vector<double> Rk4StepResponse(const StateSpace& block, double period,
                                    int samples) {
  const int substeps = 20;
  const double h = period / substeps;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(block.States());
  const auto f = [&](const Eigen::VectorXd& state) -> Eigen::VectorXd {
    return block.a * state + block.b.col(0);
  };
  std::vector<double> y;
  for (int k = 0; k < samples; ++k) {
    y.push_back((block.c * x)(0, 0) + block.d(0, 0));
    for (int i = 0; i < substeps; ++i) {
      const Eigen::VectorXd k1 = f(x);
      const Eigen::VectorXd k2 = f(x + 0.5 * h * k1);
      const Eigen::VectorXd k3 = f(x + 0.5 * h * k2);
      const Eigen::VectorXd k4 = f(x + h * k3);
      x += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
  }
  return y;
}

TEST(FractionalIntegratorTest, ZeroOrderHoldIsExactForHeldInput) {
  // For a constant error the ZOH discretisation reproduces the continuous
  // block at the samples. Measured against RK4: 7.7e-14 relative;
  // tolerance 1e-12 relative.
  FractionalIntegrator::Config config;
  config.clamp_enabled = false;
  FractionalIntegrator integrator(config);
  const int samples = 3000;
  const std::vector<double> reference =
      Rk4StepResponse(integrator.continuous(), config.sample_period_s, samples);
  for (int k = 0; k < samples; ++k) {
    const double u = integrator.Update(1.0);
    EXPECT_NEAR(u, reference[k], 1e-12 * std::abs(reference[k])) << k;
  }
  // The step response grows like K t^0.62 / Gamma(1.62) inside the band
  // (measured 1.6 % above it at t = 3 s with N = 4).
  const double t = samples * config.sample_period_s;
  EXPECT_NEAR(integrator.last_output() /
                  (15.62 * std::pow(t, 0.62) / std::tgamma(1.62)),
              1.0, 0.05);
}

// Eq. 15 realised in closed loop (realisation kEq15): the cascade of the
// printed quartics' roots is the printed transfer function.
TEST(FractionalIntegratorTest, Eq15RealisationIsThePrintedFilter) {
  FractionalIntegrator::Config config;
  config.realisation = FractionalRealisation::kEq15;
  const FractionalIntegrator integrator(config);
  EXPECT_EQ(integrator.continuous().States(), 4);
  // Measured over [1e-4, 1e4] rad/s: 1.2e-14 relative (the roots are
  // polished on the printed polynomials, so this is rounding); tolerance
  // 1e-12.
  double worst = 0;
  for (double w = 1e-4; w <= 1e4; w *= 1.1) {
    const Complex printed = Eq15Evaluate({0.0, w});
    worst = std::max(worst, std::abs(integrator.Evaluate({0.0, w}) / printed - 1.0));
  }
  EXPECT_LT(worst, 1e-12);
  // The printed zeros and poles are the N-pairs Oustaloup corners of
  // order -0.6248 on [1e-3, 1e2] rad/s (tests/oustaloup_test.cc finds the
  // order from the coefficients). Measured: largest corner difference
  // 0.042 % (the printed four significant digits); tolerance 0.4 %.
  const ZeroPoleGain printed = Eq15ZeroPoleGain();
  const ZeroPoleGain oustaloup = OustaloupZpk({-0.6248, 1e-3, 1e2, 4});
  ASSERT_EQ(printed.zero_corners_rad_s.size(), 4u);
  ASSERT_EQ(printed.pole_corners_rad_s.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(printed.zero_corners_rad_s[k] / oustaloup.zero_corners_rad_s[k], 1.0, 4e-3) << k;
    EXPECT_NEAR(printed.pole_corners_rad_s[k] / oustaloup.pole_corners_rad_s[k], 1.0, 4e-3) << k;
  }
  // Eq. 14's gain and order still describe the ideal controller.
  EXPECT_EQ(integrator.EvaluateExact({0.0, 5.0}), FractionalIntegrator(FractionalIntegrator::Config{})
                                                      .EvaluateExact({0.0, 5.0}));
}

// The zero-order hold of eq. 15 is exact for a held error: its samples are
// the continuous step response by partial fractions,
//   y(t) = H(0) + sum_k r_k exp(-p_k t),
//   r_k = g prod_j (z_j - p_k) / (-p_k prod_(j != k) (p_j - p_k)),
// with the printed corners and gain g = 32.08 / 36.47 (H(0) = 11.7 / 0.01).
TEST(FractionalIntegratorTest, Eq15ZeroOrderHoldIsExactForHeldInput) {
  const ZeroPoleGain zpk = Eq15ZeroPoleGain();
  const double dc_gain = kEq15Numerator[4] / kEq15Denominator[4];
  std::vector<double> residues;
  for (std::size_t k = 0; k < zpk.pole_corners_rad_s.size(); ++k) {
    const double p = zpk.pole_corners_rad_s[k];
    double residue = zpk.gain / -p;
    for (std::size_t j = 0; j < zpk.pole_corners_rad_s.size(); ++j) {
      residue *= zpk.zero_corners_rad_s[j] - p;
      if (j != k) residue /= zpk.pole_corners_rad_s[j] - p;
    }
    residues.push_back(residue);
  }
  FractionalIntegrator::Config config;
  config.realisation = FractionalRealisation::kEq15;
  config.clamp_enabled = false;
  FractionalIntegrator integrator(config);
  // Measured over 20 s at 1 kHz: 3.8e-13 relative (rounding); tolerance
  // 1e-11.
  double worst = 0;
  for (int k = 0; k < 20000; ++k) {
    const double t = k * config.sample_period_s;
    double expected = dc_gain;
    for (std::size_t i = 0; i < residues.size(); ++i) {
      expected += residues[i] * std::exp(-zpk.pole_corners_rad_s[i] * t);
    }
    worst = std::max(worst, std::abs(integrator.Update(1.0) / expected - 1.0));
  }
  EXPECT_LT(worst, 1e-11);
}

TEST(FractionalIntegratorTest, OrderOneIsAnExactIntegrator) {
  // lambda = 1: K/s, whose ZOH is x_(k+1) = x_k + T e_k, u_k = K x_k.
  FractionalIntegrator::Config config;
  config.order = 1.0;
  config.gain = 2.5;
  config.clamp_enabled = false;
  FractionalIntegrator integrator(config);
  EXPECT_NEAR(std::abs(integrator.Evaluate({0.0, 3.0}) - 2.5 / Complex(0, 3)),
              0.0, 1e-12);
  for (int k = 0; k < 100; ++k) {
    EXPECT_NEAR(integrator.Update(1.0), 2.5 * 1e-3 * k, 1e-12);
  }
}

TEST(FractionalIntegratorTest, ClampWithConditionalIntegration) {
  FractionalIntegrator::Config config;  // clamp at 6 V
  FractionalIntegrator clamped(config);
  config.clamp_enabled = false;
  FractionalIntegrator linear(config);
  // e = 1 mm for 2 s: unclamped, 15.62 t^0.62 / Gamma(1.62) > 6 V after
  // about 0.2 s.
  double u = 0;
  for (int k = 0; k < 2000; ++k) {
    u = clamped.Update(1.0);
    EXPECT_LE(u, 6.0);
    linear.Update(1.0);
  }
  EXPECT_EQ(u, 6.0);
  EXPECT_GT(linear.last_output(), 20.0);
  // The held state keeps the unclamped output near the limit (one sample
  // of growth beyond it at most), so reversing the error leaves saturation
  // at once.
  const double unclamped_now = (clamped.discrete().c * clamped.state())(0, 0) +
                               clamped.discrete().d(0, 0) * 1.0;
  EXPECT_LT(unclamped_now, 6.5);
  u = clamped.Update(-0.5);
  EXPECT_LT(u, 6.0);
  EXPECT_GT(linear.Update(-0.5), 6.0);  // the linear one is far beyond
  clamped.Reset();
  EXPECT_EQ(clamped.state().norm(), 0.0);
}

TEST(FractionalIntegratorTest, RejectsBadConfiguration) {
  const auto expect_field =
      [](const std::function<void(FractionalIntegrator::Config&)>& edit,
         const std::string& field) {
        FractionalIntegrator::Config config;
        edit(config);
        ExpectThrowMentioning<std::invalid_argument>(
            [&] { FractionalIntegrator integrator(config); }, field);
      };
  expect_field([](auto& c) { c.gain = -15.62; }, "gain");
  expect_field([](auto& c) { c.order = 0; }, "order");
  expect_field([](auto& c) { c.order = -0.62; }, "order");
  expect_field([](auto& c) { c.order = 1.2; }, "order");
  expect_field([](auto& c) { c.oustaloup_n = 0; }, "oustaloup_n");
  expect_field([](auto& c) { c.w_low_rad_s = 0; }, "w_low_rad_s");
  expect_field([](auto& c) { c.w_high_rad_s = 1e-3; }, "w_high_rad_s");
  expect_field([](auto& c) { c.w_high_rad_s = 1e-4; }, "w_high_rad_s");
  expect_field([](auto& c) { c.sample_period_s = 0; }, "sample_period_s");
  expect_field([](auto& c) { c.v_max = 0; }, "v_max");
  ExpectThrowMentioning<std::invalid_argument>(
      [] { DiscretizeZeroOrderHold(Gain(1.0), -1.0); }, "sample_period_s");
}

}  // namespace
// ------------------------------------------- first-order sections ---

// The sections' difference equations (controllers/first_order_sections.h),
// as the exported C runs them, in double or float.
template <typename Real>
std::vector<double> RunSections(const ParallelSections& sections,
                                const std::vector<double>& error) {
  std::vector<Real> x(sections.sections.size(), Real(0));
  std::vector<double> output;
  for (double e_double : error) {
    const Real e = static_cast<Real>(e_double);
    Real u = static_cast<Real>(sections.d) * e;
    for (size_t i = 0; i < x.size(); ++i) u += static_cast<Real>(sections.sections[i].c) * x[i];
    for (size_t i = 0; i < x.size(); ++i) {
      x[i] += static_cast<Real>(sections.sections[i].b) * e -
              static_cast<Real>(sections.sections[i].alpha) * x[i];
    }
    output.push_back(u);
  }
  return output;
}

// A deterministic error over 20 s at 1 kHz: a ramp-in, two sines and a step.
std::vector<double> TestError() {
  std::vector<double> error;
  for (int k = 0; k < 20000; ++k) {
    const double t = 1e-3 * k;
    error.push_back(0.3 * std::sin(2.0 * t) + 0.1 * std::sin(31.0 * t) + (t > 7.0 ? 0.2 : 0.0));
  }
  return error;
}

// The sections are the integrator's own discrete block: the same outputs
// as FractionalIntegrator::Update (no clamp) to rounding, for eq. 14's
// Oustaloup realisation, eq. 15, an order-1 integrator (a pole at z = 1)
// and s^-0.5 with N = 5 down to 0.01 rad/s.
TEST(FirstOrderSections, RunTheIntegratorsDiscreteBlock) {
  std::vector<FractionalIntegrator::Config> configs(4);
  configs[1].realisation = FractionalRealisation::kEq15;
  configs[2].order = 1.0;
  configs[3].order = 0.5, configs[3].oustaloup_n = 5, configs[3].w_low_rad_s = 0.01;
  const std::vector<double> error = TestError();
  for (FractionalIntegrator::Config config : configs) {
    config.clamp_enabled = false;
    FractionalIntegrator integrator(config);
    const ParallelSections sections = ParallelFirstOrderSections(integrator.discrete());
    EXPECT_EQ(sections.sections.size(), static_cast<size_t>(integrator.discrete().a.rows()));
    const std::vector<double> ours = RunSections<double>(sections, error);
    double worst = 0, largest = 0;
    for (size_t k = 0; k < error.size(); ++k) {
      const double u = integrator.Update(error[k]);
      worst = std::max(worst, std::abs(ours[k] - u));
      largest = std::max(largest, std::abs(u));
    }
    // Measured: up to 3e-14 of the largest output.
    EXPECT_LT(worst, 1e-12 * largest) << config.order << " " << config.oustaloup_n;
  }
}

// Each section keeps 1 - p: float32 rounds alpha to 6e-8 of itself, so a
// corner moves by 1e-7 at most; the pole itself in float moves the slowest
// corner of s^-0.5 with N = 5 on [0.01, 100] rad/s (p = 0.99998415, 0.01585
// rad/s) by 3.8e-4 (measured; float's spacing below 1 is 6e-8, 1 - p is
// 1.6e-5). And the float sections follow the double ones to 1e-5 of the
// largest output over 20 s.
TEST(FirstOrderSections, KeepTheirCornersInFloat) {
  FractionalIntegrator::Config config;
  config.order = 0.5, config.oustaloup_n = 5, config.w_low_rad_s = 0.01;
  config.clamp_enabled = false;
  const FractionalIntegrator integrator(config);
  const ParallelSections sections = ParallelFirstOrderSections(integrator.discrete());
  const FirstOrderSection& slowest = sections.sections.front();
  EXPECT_NEAR(slowest.pole(), 0.99998415, 1e-8);
  const double alpha_float = static_cast<float>(slowest.alpha);
  const double alpha_of_pole_float = 1.0 - static_cast<double>(static_cast<float>(slowest.pole()));
  EXPECT_LT(std::abs(alpha_float / slowest.alpha - 1), 1e-7);
  EXPECT_GT(std::abs(alpha_of_pole_float / slowest.alpha - 1), 1e-4);
  const std::vector<double> error = TestError();
  const std::vector<double> exact = RunSections<double>(sections, error);
  const std::vector<double> single = RunSections<float>(sections, error);
  double worst = 0, largest = 0;
  for (size_t k = 0; k < error.size(); ++k) {
    worst = std::max(worst, std::abs(single[k] - exact[k]));
    largest = std::max(largest, std::abs(exact[k]));
  }
  EXPECT_LT(worst, 1e-5 * largest);
}

}  // namespace ipmc
