// Sampled controllers (PID of eq. 12, fractional integrator of eq. 14/15)
// and the closed-loop step responses of section 5.2.
//
// Independent references used below:
//  - closed forms (discrete PID recursions, ZOH of 1/s, first- and
//    second-order step responses);
//  - a fine RK4 integration of the continuous Oustaloup realisation (for
//    the exactness of the zero-order-hold discretisation);
//  - the continuous closed loop with the exact s^-0.5 and s^-0.62, inverted
//    numerically from the Laplace domain with mpmath (invertlaplace, de Hoog
//    and Talbot agreeing to 2e-12) - the "exact" values quoted below;
//  - DESIGN.md's "computed" column (numpy/scipy/mpmath, rounded).
#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/test_util.h"
#include "controllers/closed_loop.h"
#include "controllers/fractional_integrator.h"
#include "controllers/linear/oustaloup.h"
#include "controllers/paper_eq15.h"
#include "controllers/pid.h"
#include "controllers/reference_model.h"
#include "controllers/linear/state_space.h"
#include "plugin/base/numbers.h"

namespace ipmc {
namespace {

using ::ipmc::testing::ExpectThrowMentioning;

using Complex = std::complex<double>;


double Db(Complex h) { return 20 * std::log10(std::abs(h)); }
double Deg(Complex h) { return std::arg(h) * 180 / kPi; }

// ---------------------------------------------------------------- PID ---

PidController::Config LinearPid(double sample_period_s = 1e-3) {
  PidController::Config config;  // eq. 12 gains
  config.clamp_enabled = false;
  config.sample_period_s = sample_period_s;
  return config;
}

TEST(PidTest, DefaultsAreEquation12) {
  const PidController::Config config;
  EXPECT_EQ(config.kp, 8.12);
  EXPECT_EQ(config.ki, 53.36);
  EXPECT_EQ(config.kd, 0.61);
  EXPECT_EQ(config.sample_period_s, 1e-3);
  EXPECT_TRUE(config.clamp_enabled);
  EXPECT_EQ(config.v_max, 6.0);
}

TEST(PidTest, ConstantErrorFollowsTheDiscreteRecursions) {
  // Backward-Euler integral and backward-difference derivative, from rest:
  // u_0 = Kp + Ki T + Kd / T, u_k = Kp + Ki T (k + 1) for k >= 1.
  const double period = 1e-3;
  PidController pid(LinearPid(period));
  for (int k = 0; k < 100; ++k) {
    const double expected =
        8.12 + 53.36 * period * (k + 1) + (k == 0 ? 0.61 / period : 0.0);
    EXPECT_NEAR(pid.Update(1.0), expected, 1e-12) << "k = " << k;
  }
  // Filtered derivative: D_k = Kd / (Tf + T) (Tf / (Tf + T))^k.
  PidController::Config config = LinearPid(period);
  config.kp = 0;
  config.ki = 0;
  config.derivative_filter_time_s = 4e-3;
  PidController filtered(config);
  const double tf = config.derivative_filter_time_s;
  for (int k = 0; k < 50; ++k) {
    EXPECT_NEAR(filtered.Update(2.0),
                2.0 * 0.61 / (tf + period) * std::pow(tf / (tf + period), k),
                1e-12);
  }
}

TEST(PidTest, ContinuousResponseAndFilterFromN) {
  PidController::Config config;
  const PidController ideal(config);
  const Complex s(0.0, 5.0);
  EXPECT_NEAR(std::abs(ideal.Evaluate(s) - (8.12 + 53.36 / s + 0.61 * s)), 0.0,
              1e-13);
  // DESIGN.md: PID(j5) 20.94 dB, -43.19 deg (measured 20.9352, -43.1880).
  EXPECT_NEAR(Db(ideal.Evaluate(s)), 20.94, 0.01);
  EXPECT_NEAR(Deg(ideal.Evaluate(s)), -43.19, 0.01);

  config.derivative_filter_time_s =
      PidController::DerivativeFilterTimeFromN(8.12, 0.61, 10.0);
  EXPECT_NEAR(config.derivative_filter_time_s, 0.61 / (8.12 * 10.0), 1e-18);
  const PidController filtered(config);
  // The derivative gain levels off at Kd / Tf = N Kp.
  const Complex high(0.0, 1e9);
  EXPECT_NEAR(filtered.Evaluate(high).real(), 8.12 + 10.0 * 8.12, 1e-6);
  ExpectThrowMentioning<std::invalid_argument>(
      [] { PidController::DerivativeFilterTimeFromN(0.0, 0.61, 10.0); }, "kp");
  ExpectThrowMentioning<std::invalid_argument>(
      [] { PidController::DerivativeFilterTimeFromN(8.12, 0.61, 0.0); }, "n");
}

TEST(PidTest, ClampWithConditionalIntegration) {
  PidController::Config config;  // clamp at 6 V, eq. 12 gains
  config.kd = 0;
  PidController pid(config);
  // e = 0.5 mm: Kp e = 4.06 V; the integral adds 26.68 V/s until the
  // output reaches 6 V (about 73 ms), then stops exactly at the limit.
  double u = 0;
  for (int k = 0; k < 2000; ++k) {
    u = pid.Update(0.5);
    EXPECT_LE(u, 6.0);
  }
  EXPECT_EQ(u, 6.0);
  EXPECT_NEAR(pid.integral(), 6.0 - 8.12 * 0.5, 1e-12);
  // The error reverses: no wound-up integral, the output leaves the limit
  // at once (Kp * -0.1 + ~1.94 V).
  u = pid.Update(-0.1);
  EXPECT_LT(u, 6.0);
  EXPECT_NEAR(u, -0.812 + pid.integral(), 1e-12);
  EXPECT_NEAR(u, 1.13, 0.03);

  // Negative saturation is symmetric.
  pid.Reset();
  for (int k = 0; k < 2000; ++k) u = pid.Update(-0.5);
  EXPECT_EQ(u, -6.0);
  EXPECT_NEAR(pid.integral(), -(6.0 - 8.12 * 0.5), 1e-12);
  // With P alone beyond the limit, the integral holds.
  pid.Reset();
  for (int k = 0; k < 100; ++k) u = pid.Update(1.0);
  EXPECT_EQ(u, 6.0);
  EXPECT_EQ(pid.integral(), 0.0);

  // Without the clamp the integral keeps growing (linear controller).
  PidController linear(LinearPid());
  for (int k = 0; k < 2000; ++k) u = linear.Update(0.5);
  EXPECT_NEAR(u, 8.12 * 0.5 + 53.36 * 2.0 * 0.5, 1e-9);
}

TEST(PidTest, ResetRestoresRest) {
  PidController pid(PidController::Config{});
  std::vector<double> first;
  for (int k = 0; k < 50; ++k) first.push_back(pid.Update(std::sin(0.1 * k)));
  pid.Reset();
  EXPECT_EQ(pid.integral(), 0.0);
  for (int k = 0; k < 50; ++k) {
    EXPECT_EQ(pid.Update(std::sin(0.1 * k)), first[k]);  // bit-identical
  }
}

TEST(PidTest, RejectsBadConfiguration) {
  const auto expect_field =
      [](const std::function<void(PidController::Config&)>& edit,
         const std::string& field) {
        PidController::Config config;
        edit(config);
        ExpectThrowMentioning<std::invalid_argument>(
            [&] { PidController pid(config); }, field);
      };
  expect_field([](auto& c) { c.kp = -1; }, "kp");
  expect_field([](auto& c) { c.ki = -1e-3; }, "ki");
  expect_field([](auto& c) { c.kd = -0.61; }, "kd");
  expect_field([](auto& c) { c.kd = std::nan(""); }, "kd");
  expect_field([](auto& c) { c.derivative_filter_time_s = -1e-3; },
               "derivative_filter_time_s");
  expect_field([](auto& c) { c.sample_period_s = 0; }, "sample_period_s");
  expect_field([](auto& c) { c.sample_period_s = -1e-3; }, "sample_period_s");
  expect_field([](auto& c) { c.v_max = 0; }, "v_max");
  expect_field([](auto& c) { c.v_max = -6; }, "v_max");
  // V_max is not used, so not checked, without the clamp.
  PidController::Config unclamped;
  unclamped.clamp_enabled = false;
  unclamped.v_max = 0;
  EXPECT_NO_THROW(PidController pid(unclamped));
  // The message is one line and states the allowed range.
  try {
    PidController::Config config;
    config.kp = -1;
    PidController pid(config);
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos);
    EXPECT_NE(message.find(">= 0"), std::string::npos) << message;
  }
  PidController pid(PidController::Config{});
  ExpectThrowMentioning<std::invalid_argument>(
      [&] { pid.Update(std::nan("")); }, "error");
}

// ------------------------------------------------ fractional integrator ---

FractionalIntegrator::Config WideBandIntegrator(double sample_period_s) {
  // "Exact-ish" realisation: 20 pairs on [1e-5, 1e5] rad/s (two per decade).
  FractionalIntegrator::Config config;  // eq. 14 gain and order
  config.oustaloup_n = 20;
  config.w_low_rad_s = 1e-5;
  config.w_high_rad_s = 1e5;
  config.clamp_enabled = false;
  config.sample_period_s = sample_period_s;
  return config;
}

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
  // DESIGN.md: 15.21 dB, -55.80 deg (measured 15.2064 dB, -55.8 deg: the
  // phase is exactly -0.62 * 90 deg).
  const FractionalIntegrator integrator(FractionalIntegrator::Config{});
  const Complex h = integrator.EvaluateExact({0.0, 5.0});
  EXPECT_NEAR(Db(h), 15.21, 0.01);
  EXPECT_NEAR(Deg(h), -55.80, 1e-12);
}

TEST(FractionalIntegratorTest, RealisationAgainstEquation15AndExact) {
  // Eq. 15 as printed (controllers/paper_eq15.h).
  const auto eq15 = [](double w) { return Eq15Evaluate({0.0, w}); };
  // DESIGN.md: eq. 15 is the N-pairs approximation of order -0.6248 to
  // 0.05 % in its coefficients; with -0.62 it differs by 3 % / 0.27 dB.
  // Measured over [1e-3, 1e3] rad/s: order 0.6248, max |ratio - 1| 5.5e-4
  // (tolerance 1e-3); order 0.62, max 0.274 dB and 0.448 deg (tolerances
  // 0.3 dB, 0.5 deg).
  FractionalIntegrator::Config config;
  config.order = 0.6248;
  const FractionalIntegrator printed(config);
  const FractionalIntegrator paper(FractionalIntegrator::Config{});
  double worst_ratio = 0, worst_db = 0, worst_deg = 0;
  for (double w = 1e-3; w <= 1e3; w *= 1.1) {
    worst_ratio = std::max(
        worst_ratio, std::abs(printed.Evaluate({0.0, w}) / eq15(w) - 1.0));
    const Complex ratio = paper.Evaluate({0.0, w}) / eq15(w);
    worst_db = std::max(worst_db, std::abs(Db(ratio)));
    worst_deg = std::max(worst_deg, std::abs(Deg(ratio)));
  }
  EXPECT_LT(worst_ratio, 1e-3);
  EXPECT_LT(worst_db, 0.3);
  EXPECT_LT(worst_deg, 0.5);

  // The wide-band realisation follows K (j w)^-0.62 closely in the
  // decades that matter for the loop. Measured on [1e-2, 1e2] rad/s:
  // 0.0031 dB, 0.055 deg; tolerances 0.03 dB and 0.5 deg.
  const FractionalIntegrator wide(WideBandIntegrator(1e-3));
  double wide_db = 0, wide_deg = 0;
  for (double w = 1e-2; w <= 1e2; w *= 1.05) {
    const Complex ratio =
        wide.Evaluate({0.0, w}) / wide.EvaluateExact({0.0, w});
    wide_db = std::max(wide_db, std::abs(Db(ratio)));
    wide_deg = std::max(wide_deg, std::abs(Deg(ratio)));
  }
  EXPECT_LT(wide_db, 0.03);
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

// ------------------------------------------------------------ closed loop

TEST(ClosedLoopTest, PlantIsAdvancedExactlyBetweenSamples) {
  // A controller that always outputs 1 V into 1/(s + 1): y = 1 - e^-t at
  // every recorded point, samples and sub-steps alike (2100 products with
  // the one-sub-step matrix exponential: measured 6.6e-14, tolerance
  // 5e-13).
  const StateSpace lag = SecondOrderLag(1.0, 1.0, 0.0);
  StepSimulation simulation;
  simulation.horizon_s = 3.0;
  simulation.output_substeps = 7;
  const ClosedLoopResponse response = SimulateClosedLoopStep(
      lag, [](double) { return 1.0; }, 0.01, simulation);
  ASSERT_EQ(response.time_s.size(), 300u * 7 + 1);
  EXPECT_NEAR(response.time_s.back(), 3.0, 1e-12);
  for (std::size_t i = 0; i < response.time_s.size(); ++i) {
    EXPECT_NEAR(response.output[i], 1.0 - std::exp(-response.time_s[i]), 5e-13);
    EXPECT_EQ(response.control[i], 1.0);
  }
}

TEST(ClosedLoopTest, SampledLoopFollowsTheDifferenceEquation) {
  // P controller K on 1/s with sample-and-hold: y_(k+1) = y_k + T K (A - y_k).
  const double k_p = 4.0, period = 0.05, amplitude = 2.0;
  PidController::Config config;
  config.kp = k_p;
  config.ki = 0;
  config.kd = 0;
  config.clamp_enabled = false;
  config.sample_period_s = period;
  PidController pid(config);
  StepSimulation simulation;
  simulation.horizon_s = 2.0;
  simulation.step_amplitude = amplitude;
  const ClosedLoopResponse response =
      SimulateClosedLoopStep(Integrators(1), pid, simulation);
  ASSERT_EQ(response.time_s.size(), 41u);
  double y = 0;
  for (std::size_t i = 0; i < response.time_s.size(); ++i) {
    EXPECT_NEAR(response.output[i], y, 1e-13) << i;
    y += period * k_p * (amplitude - y);
  }
}

TEST(ClosedLoopTest, StepMetricsOfAnalyticResponses) {
  // First order 1 - e^-t: rise (10-90 %) ln 9, 2 % settling ln 50.
  std::vector<double> t, y;
  for (int i = 0; i <= 100000; ++i) {
    t.push_back(i * 1e-4);
    y.push_back(1.0 - std::exp(-t.back()));
  }
  StepMetrics metrics = ComputeStepMetrics(t, y, 1.0);
  EXPECT_NEAR(*metrics.rise_time_s, std::log(9.0), 1e-8);
  EXPECT_NEAR(*metrics.settling_time_s, std::log(50.0), 1e-8);
  EXPECT_EQ(metrics.overshoot_percent, 0.0);

  // Second order, zeta = 0.3, w_n = 2: overshoot exp(-pi zeta /
  // sqrt(1 - zeta^2)), peak at pi / w_d. Scaled by a final value of -3
  // (a negative step works the same).
  const double zeta = 0.3, w_n = 2.0, w_d = w_n * std::sqrt(1 - zeta * zeta);
  const double pi = kPi;
  t.clear();
  y.clear();
  for (int i = 0; i <= 20000; ++i) {
    t.push_back(i * 1e-3);
    y.push_back(-3.0 * (1.0 - std::exp(-zeta * w_n * t.back()) *
                                  (std::cos(w_d * t.back()) +
                                   zeta / std::sqrt(1 - zeta * zeta) *
                                       std::sin(w_d * t.back()))));
  }
  metrics = ComputeStepMetrics(t, y, -3.0);
  EXPECT_NEAR(metrics.overshoot_percent,
              100 * std::exp(-pi * zeta / std::sqrt(1 - zeta * zeta)), 1e-6);
  EXPECT_NEAR(metrics.peak_time_s, pi / w_d, 1e-6);
  EXPECT_NEAR(metrics.peak_value,
              -3.0 * (1 + std::exp(-pi * zeta / std::sqrt(1 - zeta * zeta))),
              1e-8);
  ASSERT_TRUE(metrics.settling_time_s.has_value());

  // Still outside the band at the end: no settling time.
  metrics = ComputeStepMetrics({0.0, 1.0, 2.0}, {0.0, 0.5, 0.9}, 1.0);
  EXPECT_FALSE(metrics.settling_time_s.has_value());
  EXPECT_TRUE(metrics.rise_time_s.has_value());
  ExpectThrowMentioning<std::invalid_argument>(
      [] {
        ComputeStepMetrics({0.0, 1.0}, {0.0, 1.0}, 0.0);
      },
      "final_value");
  ExpectThrowMentioning<std::invalid_argument>(
      [] {
        ComputeStepMetrics({0.0, 0.0}, {0.0, 1.0}, 1.0);
      },
      "increasing");
}

TEST(ClosedLoopTest, CostOfEquation11) {
  // y = y_r + c: J = c int_0^H (1/2 + t/2) dt = c (H/2 + H^2/4), which the
  // trapezoidal rule integrates exactly.
  const ReferenceModel model;
  std::vector<double> t, y;
  for (int i = 0; i <= 2000; ++i) {
    t.push_back(i * 1e-3);
    y.push_back(model.StepResponse(t.back()) - 0.01);
  }
  EXPECT_NEAR(ReferenceModelCost(t, y, model, 1.0, 2.0), 0.01 * (1.0 + 1.0),
              1e-14);
  // A horizon inside the last interval is interpolated (linearly in y, so
  // not exactly: measured 3.2e-12, tolerance 3e-11).
  EXPECT_NEAR(ReferenceModelCost(t, y, model, 1.0, 1.2345),
              0.01 * (1.2345 / 2 + 1.2345 * 1.2345 / 4), 3e-11);
  ExpectThrowMentioning<std::invalid_argument>(
      [&] { ReferenceModelCost(t, y, model, 1.0, 3.0); }, "horizon_s");
}

TEST(ClosedLoopTest, RejectsBadSimulation) {
  PidController pid(PidController::Config{});
  StepSimulation simulation;
  simulation.horizon_s = 0;
  ExpectThrowMentioning<std::invalid_argument>(
      [&] { SimulateClosedLoopStep(Integrators(1), pid, simulation); },
      "horizon_s");
  simulation = {};
  simulation.output_substeps = 0;
  ExpectThrowMentioning<std::invalid_argument>(
      [&] { SimulateClosedLoopStep(Integrators(1), pid, simulation); },
      "output_substeps");
  simulation = {};
  simulation.step_amplitude = 0;
  ExpectThrowMentioning<std::invalid_argument>(
      [&] { SimulateClosedLoopStep(Integrators(1), pid, simulation); },
      "step_amplitude");
  simulation = {};
  simulation.max_horizon_s = -1.0;
  ExpectThrowMentioning<std::invalid_argument>(
      [&] { SimulateClosedLoopStep(Integrators(1), pid, simulation); },
      "max_horizon_s");
  simulation = {};
  simulation.settling_band = 1.0;
  ExpectThrowMentioning<std::invalid_argument>(
      [&] { SimulateClosedLoopStep(Integrators(1), pid, simulation); },
      "settling_band");
  ExpectThrowMentioning<std::invalid_argument>(
      [&] {
        SimulateClosedLoopStep(Integrators(1), [](double e) { return e; }, 0.0,
                               {});
      },
      "sample_period_s");
}

// ------------------------------------------- section 5.2 step responses ---

// P_q = s^-0.5 G1_q (Table 2; links 1 and 2 with link 3's damping ratio
// 0.2525), s^-0.5 realised with 20 Oustaloup pairs on [1e-5, 1e5] rad/s.
StateSpace LinkPlant(int link) {
  const double a0[3] = {13.70e-3, 51.00e-3, 376.09e-3};
  const double b2[3] = {1.62e-3, 1.61e-3, 2.13e-3};
  const double b1 = link == 3 ? 23.31e-3 : 2 * 0.2525 * std::sqrt(b2[link - 1]);
  OustaloupConfig half_integrator;
  half_integrator.order = -0.5;
  half_integrator.w_low_rad_s = 1e-5;
  half_integrator.w_high_rad_s = 1e5;
  half_integrator.n = 20;
  return Series(OustaloupStateSpace(half_integrator),
                SecondOrderLag(a0[link - 1], b1, b2[link - 1]));
}

struct LinkOvershoots {
  double pid[3];  // links 1, 2, 3
  double fractional[3];
};

LinkOvershoots Overshoots(double sample_period_s) {
  LinkOvershoots result{};
  for (int link = 1; link <= 3; ++link) {
    const StateSpace plant = LinkPlant(link);
    StepSimulation simulation;
    // Link 1 is the slowest (gain 27 times link 3's): its C_I peak is at
    // about 16 s.
    simulation.horizon_s = link == 1 ? 40.0 : 20.0;
    PidController pid(LinearPid(sample_period_s));
    FractionalIntegrator integrator(WideBandIntegrator(sample_period_s));
    result.pid[link - 1] =
        ComputeStepMetrics(SimulateClosedLoopStep(plant, pid, simulation))
            .overshoot_percent;
    result.fractional[link - 1] =
        ComputeStepMetrics(
            SimulateClosedLoopStep(plant, integrator, simulation))
            .overshoot_percent;
  }
  return result;
}

TEST(PaperStepResponsesTest, OvershootNearContinuousValuesAt10kHz) {
  // Exact continuous loop (mpmath inverse Laplace, see the file comment),
  // links 1/2/3: PID 25.1840 / 20.1396 / 9.0341 %, C_I 3.6199 / 3.6821 /
  // 5.5201 %. Measured here at T = 0.1 ms: PID 25.1786 / 20.1405 / 9.0338,
  // C_I 3.6243 / 3.6876 / 5.5417 (the C_I residual is the Oustaloup ripple
  // of the controller). Tolerances 0.05 (PID) and 0.2 (C_I) points.
  const LinkOvershoots overshoot = Overshoots(1e-4);
  const double exact_pid[3] = {25.1840, 20.1396, 9.0341};
  const double exact_fractional[3] = {3.6199, 3.6821, 5.5201};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(overshoot.pid[i], exact_pid[i], 0.05) << "link " << i + 1;
    EXPECT_NEAR(overshoot.fractional[i], exact_fractional[i], 0.2)
        << "link " << i + 1;
  }
}

TEST(PaperStepResponsesTest, OvershootAtTheDefault1kHz) {
  // DESIGN.md, links 3/2/1: C_I 5.5 / 3.7 / 3.6 %, PID 9.0 / 20.3 / 25.3 %.
  // Measured at 1 kHz: C_I 5.6847 / 3.6920 / 3.6256, PID 9.0083 / 20.1365 /
  // 25.1778. The continuous loop gives PID 20.14 / 25.18 for links 2/1
  // (previous test), 0.16 and 0.12 below DESIGN.md's rounded values; the
  // 1 kHz sampling adds 0.16 points to C_I on link 3. Tolerance 0.25
  // points against DESIGN.md.
  const LinkOvershoots overshoot = Overshoots(1e-3);
  const double design_pid[3] = {25.3, 20.3, 9.0};
  const double design_fractional[3] = {3.6, 3.7, 5.5};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(overshoot.pid[i], design_pid[i], 0.25) << "link " << i + 1;
    EXPECT_NEAR(overshoot.fractional[i], design_fractional[i], 0.25)
        << "link " << i + 1;
  }
  // The paper's qualitative claims: the PID overshoot grows strictly from
  // link 3 to link 1 (lower gain), the fractional integrator's stays
  // nearly constant (iso-damping): spread under 2.5 points.
  EXPECT_GT(overshoot.pid[0], overshoot.pid[1]);
  EXPECT_GT(overshoot.pid[1], overshoot.pid[2]);
  const auto [low, high] = std::minmax_element(std::begin(overshoot.fractional),
                                               std::end(overshoot.fractional));
  EXPECT_LT(*high - *low, 2.5);
}

TEST(PaperStepResponsesTest, CostOfThePaperPidAgainstTheReferenceModel) {
  // J of eq. 11, link 3, horizons 2 / 5 / 10 s. DESIGN.md: 0.0868 / 0.1100
  // / 0.1421. Continuous (mpmath inverse Laplace, trapezoid on 2 ms):
  // 0.08678 / 0.11003 / 0.14211. Measured here: at 10 kHz 0.086793 /
  // 0.110033 / 0.142154 (tolerance 1e-4 against DESIGN.md: its rounding
  // plus the plant realisation); at the default 1 kHz 0.087038 / 0.110282 /
  // 0.142405, 2.4e-4 to 3.1e-4 above (the sampled PID lags; tolerance
  // 5e-4).
  const ReferenceModel model;
  const StateSpace plant = LinkPlant(3);
  StepSimulation simulation;
  simulation.horizon_s = 10.0;
  const double horizons[3] = {2.0, 5.0, 10.0};
  const double design[3] = {0.0868, 0.1100, 0.1421};

  PidController fine(LinearPid(1e-4));
  const ClosedLoopResponse fine_response =
      SimulateClosedLoopStep(plant, fine, simulation);
  PidController standard(LinearPid(1e-3));
  const ClosedLoopResponse standard_response =
      SimulateClosedLoopStep(plant, standard, simulation);
  for (int i = 0; i < 3; ++i) {
    const double j_fine = ReferenceModelCost(fine_response, model, horizons[i]);
    const double j_standard =
        ReferenceModelCost(standard_response, model, horizons[i]);
    EXPECT_NEAR(j_fine, design[i], 1e-4) << "horizon " << horizons[i];
    EXPECT_NEAR(j_standard, design[i], 5e-4) << "horizon " << horizons[i];
    EXPECT_GT(j_standard, j_fine);
  }
}

// Each reason a record can leave its step metrics open, on responses
// whose metrics are known: records of a held controller output into
// first- and second-order lags.
TEST(ClosedLoopTest, RecordCheckNamesWhatTheRecordDoesNotDetermine) {
  const auto record = [](const StateSpace& plant, double horizon_s) {
    StepSimulation simulation;
    simulation.horizon_s = horizon_s;
    return SimulateClosedLoopStep(plant, [](double) { return 1.0; }, 0.01, simulation);
  };
  // Monotone 1 - e^-t: the maximum is always the last point.
  const StateSpace lag = SecondOrderLag(1.0, 1.0, 0.0);
  EXPECT_EQ(CheckStepRecord(record(lag, 2.0)), StepRecordStatus::kPeakAtEnd);
  EXPECT_EQ(CheckStepRecord(record(lag, 20.0)), StepRecordStatus::kPeakAtEnd);
  // 0.5 e^-t (x' = -x + u, y = -x / 2 + u / 2) starts at its peak and never
  // reaches 90 %.
  StateSpace decay;
  decay.a = Eigen::MatrixXd::Constant(1, 1, -1.0);
  decay.b = Eigen::MatrixXd::Constant(1, 1, 1.0);
  decay.c = Eigen::MatrixXd::Constant(1, 1, -0.5);
  decay.d = Eigen::MatrixXd::Constant(1, 1, 0.5);
  EXPECT_EQ(CheckStepRecord(record(decay, 5.0)), StepRecordStatus::kBelow90Percent);
  // zeta = 0.1, w_n = 1: peak at pi / w_d = 3.16 s, 2 % settling ~ 39 s.
  const StateSpace resonance = SecondOrderLag(1.0, 0.2, 1.0);
  EXPECT_EQ(CheckStepRecord(record(resonance, 10.0)), StepRecordStatus::kOutsideBand);
  const ClosedLoopResponse settled = record(resonance, 60.0);
  ASSERT_TRUE(ComputeStepMetrics(settled).settling_time_s.has_value());
  EXPECT_GT(*ComputeStepMetrics(settled).settling_time_s, 30.0);
  EXPECT_EQ(CheckStepRecord(settled), StepRecordStatus::kSettledLate);
  EXPECT_EQ(CheckStepRecord(record(resonance, 100.0)), StepRecordStatus::kDetermined);
  EXPECT_STREQ(StepRecordStatusText(StepRecordStatus::kPeakAtEnd),
               "peak at the end (still rising)");
}

// C_I on link 1 (Table 2, the slowest loop) peaks at 16.4 s and settles
// at 27.0 s: a 10 s record misses both. Extended, the record stops at the
// first multiple of the horizon that holds them (60 s: in the band for
// more than half of it) and its metrics are those of a 300 s record.
TEST(ClosedLoopTest, RecordIsExtendedUntilItsMetricsAreDetermined) {
  const StateSpace plant = LinkPlant(1);
  FractionalIntegrator integrator(WideBandIntegrator(1e-3));
  StepSimulation simulation;
  simulation.horizon_s = 10.0;
  const ClosedLoopResponse short_record = SimulateClosedLoopStep(plant, integrator, simulation);
  EXPECT_EQ(CheckStepRecord(short_record), StepRecordStatus::kPeakAtEnd);
  simulation.max_horizon_s = 300.0;
  const ClosedLoopResponse extended = SimulateClosedLoopStep(plant, integrator, simulation);
  EXPECT_NEAR(extended.time_s.back(), 60.0, 1e-9);
  EXPECT_EQ(CheckStepRecord(extended), StepRecordStatus::kDetermined);
  // The first 10 s are the short record's, sample for sample.
  for (std::size_t i = 0; i + 1 < short_record.time_s.size(); ++i) {
    ASSERT_EQ(extended.output[i], short_record.output[i]) << i;
  }
  StepSimulation whole;
  whole.horizon_s = 300.0;
  const StepMetrics long_metrics =
      ComputeStepMetrics(SimulateClosedLoopStep(plant, integrator, whole));
  const StepMetrics metrics = ComputeStepMetrics(extended);
  EXPECT_EQ(metrics.overshoot_percent, long_metrics.overshoot_percent);
  EXPECT_EQ(metrics.peak_time_s, long_metrics.peak_time_s);
  EXPECT_EQ(*metrics.rise_time_s, *long_metrics.rise_time_s);
  EXPECT_EQ(*metrics.settling_time_s, *long_metrics.settling_time_s);
  // Measured: 3.6256 % at 16.395 s, settled at 27.028 s.
  EXPECT_NEAR(metrics.overshoot_percent, 3.6256, 1e-3);
  EXPECT_NEAR(*metrics.settling_time_s, 27.028, 1e-2);

  // A cap short of that leaves the record open, at the cap.
  simulation.max_horizon_s = 25.0;
  const ClosedLoopResponse capped = SimulateClosedLoopStep(plant, integrator, simulation);
  EXPECT_NEAR(capped.time_s.back(), 25.0, 1e-9);
  EXPECT_EQ(CheckStepRecord(capped), StepRecordStatus::kOutsideBand);
}

TEST(PaperStepResponsesTest, ClampedLoopStaysWithinSixVolts) {
  // With the +-6 V clamp (Kp alone asks 8.12 V for a 1 mm step) the loop
  // still settles, thanks to the anti-windup.
  const StateSpace plant = LinkPlant(3);
  StepSimulation simulation;
  simulation.horizon_s = 10.0;
  for (const bool fractional : {false, true}) {
    ClosedLoopResponse response;
    if (fractional) {
      FractionalIntegrator::Config config = WideBandIntegrator(1e-3);
      config.clamp_enabled = true;
      FractionalIntegrator integrator(config);
      response = SimulateClosedLoopStep(plant, integrator, simulation);
    } else {
      PidController pid(PidController::Config{});
      response = SimulateClosedLoopStep(plant, pid, simulation);
    }
    for (const double u : response.control) EXPECT_LE(std::abs(u), 6.0);
    EXPECT_NEAR(response.output.back(), 1.0, 0.02) << fractional;
    const StepMetrics metrics = ComputeStepMetrics(response);
    EXPECT_TRUE(metrics.settling_time_s.has_value());
  }
}

}  // namespace
}  // namespace ipmc
