// Reference model of section 5.2 (eq. 8, 9) and the Mittag-Leffler function
// behind its step response.
//
// Expected values were computed independently with mpmath (60 digits, the
// power series E_alpha(z) = sum z^k / Gamma(alpha k + 1) summed to 1e-50),
// and are listed with the residual measured here; tolerances are about ten
// times that residual.
#include "tests/test_util.h"
#include "controllers/reference_model.h"
#include "sim/base/numbers.h"

#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace ipmc {
namespace {

using ::ipmc::testing::ExpectThrowMentioning;



struct MittagLefflerCase {
  double alpha;
  double z;
  double expected;  // mpmath, 60 digits, rounded to 17
};

// mpmath reference values (see the file comment).
const std::vector<MittagLefflerCase> kMittagLefflerCases = {
    {1.16, -2.0, 0.089256896999429626},    {1.16, -6.45, -0.043282877190703491},
    {1.16, -50.0, -0.0029875689878994102}, {1.5, -10.0, -0.10971305425274015},
    {0.5, -3.0, 0.17900115118138995},      {1.9, -20.0, 0.074019418803661214},
};

TEST(MittagLefflerTest, MatchesHighPrecisionValues) {
  // Measured residual <= 1.4e-17 over these cases; tolerance 1e-15 (a few
  // ulp of the larger values, leaving room for other long double formats).
  for (const MittagLefflerCase& c : kMittagLefflerCases) {
    EXPECT_NEAR(MittagLeffler(c.alpha, c.z), c.expected, 1e-15)
        << "alpha = " << c.alpha << ", z = " << c.z;
  }
}

TEST(MittagLefflerTest, IntegralHoldsAtTheEndsOfTheOrderRange) {
  // Integral representation (tau > 5). Near alpha = 1 the kernel is a peak
  // of height 1 / (4 cos^2(alpha pi / 2)) = 1e5 and half-width 3e-3 at
  // v = 0 that the adaptive rule must find; near alpha = 2 the pole
  // residue dominates and its rounding (tau = 158, so ulps of the cosine's
  // argument are ~3e-14) bounds the accuracy. mpmath, 330 digits (the
  // series summed to 1e-40). Measured residuals 8.5e-19, 3.2e-19 and
  // 5.1e-14; tolerances 1e-17, 1e-17 and 5e-13.
  EXPECT_NEAR(MittagLeffler(0.999, -30.0), 3.5830164124046635e-05, 1e-17);
  EXPECT_NEAR(MittagLeffler(1.001, -30.0), -3.5797072894865565e-05, 1e-17);
  EXPECT_NEAR(MittagLeffler(1.999, -25000.0), 0.11940962651182636, 5e-13);
}

TEST(MittagLefflerTest, ClosedFormsAtAlphaOneAndTwo) {
  for (const double z : {0.0, -0.3, -4.0, -30.0}) {
    EXPECT_DOUBLE_EQ(MittagLeffler(1.0, z), std::exp(z));
    EXPECT_DOUBLE_EQ(MittagLeffler(2.0, z), std::cos(std::sqrt(-z)));
    // The series agrees with the closed forms where it is accurate.
    if (z > -10) {
      EXPECT_NEAR(MittagLefflerSeries(1.0, z), std::exp(z), 1e-15);
      EXPECT_NEAR(MittagLefflerSeries(2.0, z), std::cos(std::sqrt(-z)), 1e-15);
    }
  }
}

TEST(MittagLefflerTest, IntegralRepresentationIsOneAtZero) {
  // The Hankel integral plus the pole residues sum to E(0) = 1 exactly in
  // theory; measured residual <= 2.2e-16, tolerance 2e-15.
  for (const double alpha : {0.2, 0.6, 0.95, 1.05, 1.16, 1.5, 1.95}) {
    EXPECT_NEAR(MittagLefflerIntegral(alpha, 0.0), 1.0, 2e-15)
        << "alpha = " << alpha;
  }
}

TEST(MittagLefflerTest, SeriesAndIntegralAgreeAroundTheSwitch) {
  // Both algorithms are accurate in 1 <= tau <= 8 (series cancellation is
  // at most e^8 * 1e-19 there); the dispatcher switches at tau = 5, so the
  // agreement is also the continuity of MittagLeffler at the switch.
  // Measured max difference 1.6e-15; tolerance 2e-14.
  for (const double alpha : {0.3, 0.7, 1.05, 1.16, 1.5, 1.9}) {
    for (double tau = 1.0; tau <= 8.0; tau += 0.25) {
      const double z = -std::pow(tau, alpha);
      EXPECT_NEAR(MittagLefflerSeries(alpha, z),
                  MittagLefflerIntegral(alpha, z), 2e-14)
          << "alpha = " << alpha << ", tau = " << tau;
    }
    // Just below and just above the switch the dispatcher equals both.
    const double z_switch = -std::pow(kMittagLefflerSwitchTau, alpha);
    for (const double z : {z_switch * (1 - 1e-9), z_switch * (1 + 1e-9)}) {
      EXPECT_NEAR(MittagLeffler(alpha, z), MittagLefflerSeries(alpha, z),
                  2e-14);
      EXPECT_NEAR(MittagLeffler(alpha, z), MittagLefflerIntegral(alpha, z),
                  2e-14);
    }
  }
}

TEST(MittagLefflerTest, LargeArgumentMatchesAlgebraicAsymptotics) {
  // For 0 < alpha < 2 and z -> -inf, E_alpha(z) = -sum_k z^-k /
  // Gamma(1 - alpha k) + exponentially small terms (1/Gamma = 0 at the
  // poles); at |z| = 1e4 three terms leave |z|^-4 / |Gamma(1 - 4 alpha)|,
  // at most 4e-16 here (alpha = 1.16, measured 4.1e-16).
  for (const double alpha : {0.5, 1.16, 1.5}) {
    const double z = -1e4;
    double asymptotic = 0;
    for (int k = 1; k <= 3; ++k) {
      const double argument = 1 - alpha * k;
      if (argument <= 0 && argument == std::floor(argument)) continue;
      asymptotic -= std::pow(z, -k) / std::tgamma(argument);
    }
    EXPECT_NEAR(MittagLeffler(alpha, z), asymptotic, 1e-14)
        << "alpha = " << alpha;
  }
}

TEST(MittagLefflerTest, RejectsArgumentsOutsideTheDomain) {
  ExpectThrowMentioning<std::domain_error>([] { MittagLeffler(0.0, -1.0); },
                                           "alpha");
  ExpectThrowMentioning<std::domain_error>([] { MittagLeffler(2.5, -1.0); },
                                           "alpha");
  ExpectThrowMentioning<std::domain_error>([] { MittagLeffler(1.16, 0.5); },
                                           "z");
  ExpectThrowMentioning<std::domain_error>(
      [] { MittagLeffler(1.16, std::numeric_limits<double>::quiet_NaN()); },
      "z");
  ExpectThrowMentioning<std::domain_error>(
      [] { MittagLefflerIntegral(1.0, -1.0); }, "alpha");
  ExpectThrowMentioning<std::domain_error>(
      [] { MittagLefflerSeries(1.16, -1e4); }, "cancellation");
}

TEST(ReferenceModelTest, StepResponseMatchesIndependentValues) {
  // mpmath (see the file comment): y(0.5) = 1.0102339510316141,
  // y(1) = 1.0431269829415702, first peak 1.0539220492462820 at
  // t = 0.75832996510144555 s. docs/VALIDATION.md rounds them to 1.01023, 1.04313,
  // 1.05392 at 0.758 s. Measured residuals: values 0 (to the last bit),
  // peak time 1.5e-8 s (the peak is flat); tolerances 1e-15 and 2e-7 s.
  const ReferenceModel model;
  EXPECT_EQ(model.StepResponse(0.0), 0.0);
  EXPECT_EQ(model.StepResponse(-1.0), 0.0);
  EXPECT_NEAR(model.StepResponse(0.5), 1.0102339510316141, 1e-15);
  EXPECT_NEAR(model.StepResponse(1.0), 1.0431269829415702, 1e-15);
  const auto peak = model.StepPeak();
  ASSERT_TRUE(peak.has_value());
  EXPECT_NEAR(peak->value, 1.0539220492462820, 1e-15);
  EXPECT_NEAR(peak->time_s, 0.75832996510144555, 2e-7);
  // The values the design brief quotes, at its precision.
  EXPECT_NEAR(model.StepResponse(0.5), 1.01023, 1e-5);
  EXPECT_NEAR(model.StepResponse(1.0), 1.04313, 1e-5);
  EXPECT_NEAR(peak->value, 1.05392, 1e-5);
  EXPECT_NEAR(peak->time_s, 0.758, 1e-3);
  // Settles to 1 from above at long times: y - 1 ~ -(w_c t)^-gamma /
  // Gamma(1 - gamma) > 0 for 1 < gamma < 2 (an algebraic tail).
  const double tail = -std::pow(5.0 * 1000.0, -1.16) / std::tgamma(1 - 1.16);
  EXPECT_NEAR(model.StepResponse(1000.0) - 1.0, tail, 1e-3 * tail);
}

// Grunwald-Letnikov solution of the reference model's fractional ODE
//   w_c^-gamma D^gamma y + y = 1,  y = y' = 0 at t = 0,
// (for zero initial conditions the Riemann-Liouville and Caputo derivatives
// coincide), implicit in y_n; first order in h.
std::vector<double> GrunwaldLetnikovStep(double w_c, double gamma, double h,
                                         int steps) {
  std::vector<double> weights(steps + 1);
  weights[0] = 1.0;
  for (int j = 1; j <= steps; ++j) {
    weights[j] = weights[j - 1] * (1.0 - (gamma + 1.0) / j);
  }
  const double scale = std::pow(h * w_c, -gamma);
  std::vector<double> y(steps + 1, 0.0);
  for (int n = 1; n <= steps; ++n) {
    double history = 0;
    for (int j = 1; j <= n; ++j) history += weights[j] * y[n - j];
    y[n] = (1.0 - scale * history) / (1.0 + scale);
  }
  return y;
}

TEST(ReferenceModelTest, StepResponseMatchesGrunwaldLetnikovSimulation) {
  // Richardson extrapolation of GL with h = 2e-4 and 1e-4 s (first order)
  // against the Mittag-Leffler form. Measured difference <= 5.1e-8 on
  // [0.1, 1.2] s (1.1e-4 without the extrapolation); tolerance 5e-7.
  const ReferenceModel model;
  const double gamma = model.config().order;
  const double w_c = model.config().crossover_rad_s;
  const double h = 1e-4;
  const int steps = 12000;
  const std::vector<double> fine = GrunwaldLetnikovStep(w_c, gamma, h, steps);
  const std::vector<double> coarse =
      GrunwaldLetnikovStep(w_c, gamma, 2 * h, steps / 2);
  double max_difference = 0;
  for (int n = 1000; n <= steps; n += 500) {
    const double extrapolated = 2 * fine[n] - coarse[n / 2];
    max_difference = std::max(
        max_difference, std::abs(extrapolated - model.StepResponse(n * h)));
  }
  EXPECT_LT(max_difference, 5e-7);
}

TEST(ReferenceModelTest, FrequencyResponsesFollowEquations8And9) {
  const ReferenceModel model;
  const std::complex<double> j_wc(0.0, 5.0);
  const std::complex<double> open_loop = model.OpenLoop(j_wc);
  EXPECT_NEAR(std::abs(open_loop), 1.0, 1e-15);
  EXPECT_NEAR(std::arg(open_loop), -1.16 * kPi / 2, 1e-15);
  // Phase margin 180 - 1.16 * 90 = 75.6 deg at the crossover.
  EXPECT_NEAR(180.0 + std::arg(open_loop) * 180.0 / kPi, 75.6, 1e-12);
  // Constant phase at every frequency, slope -20 gamma dB/dec.
  const std::complex<double> decade_up = model.OpenLoop({0.0, 50.0});
  EXPECT_NEAR(20 * std::log10(std::abs(decade_up)), -20 * 1.16, 1e-12);
  EXPECT_NEAR(std::arg(decade_up), -1.16 * kPi / 2, 1e-15);
  for (const double w : {0.1, 5.0, 300.0}) {
    const std::complex<double> s(0.0, w);
    const std::complex<double> l = model.OpenLoop(s);
    EXPECT_NEAR(std::abs(model.ClosedLoop(s) - l / (1.0 + l)), 0.0, 1e-15);
  }
}

TEST(ReferenceModelTest, RejectsBadConfiguration) {
  ReferenceModel::Config config;
  config.crossover_rad_s = 0;
  ExpectThrowMentioning<std::invalid_argument>(
      [&] { ReferenceModel model(config); }, "crossover_rad_s");
  config = {};
  config.order = 2.5;
  ExpectThrowMentioning<std::invalid_argument>(
      [&] { ReferenceModel model(config); }, "order");
  config.order = 0;
  ExpectThrowMentioning<std::invalid_argument>(
      [&] { ReferenceModel model(config); }, "order");
}

TEST(ReferenceModelTest, MonotoneForOrderAtMostOne) {
  ReferenceModel::Config config;
  config.order = 0.8;
  const ReferenceModel model(config);
  EXPECT_FALSE(model.StepPeak().has_value());
  double previous = 0;
  for (double t = 0.01; t < 20; t *= 1.3) {
    const double y = model.StepResponse(t);
    EXPECT_GT(y, previous);
    EXPECT_LT(y, 1.0);
    previous = y;
  }
}

}  // namespace
}  // namespace ipmc
