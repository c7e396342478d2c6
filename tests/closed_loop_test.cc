// Closed-loop step simulations (controllers/closed_loop.h): the plant
// advanced exactly between samples, step metrics, the cost J of eq. 11,
// records extended until their metrics are determined; and the closed-loop
// step responses of section 5.2 with both controllers.
//
// Independent references used below:
//  - closed forms (first- and second-order step responses);
//  - the continuous closed loop with the exact s^-0.5 and s^-0.62, inverted
//    numerically from the Laplace domain with mpmath (invertlaplace, de Hoog
//    and Talbot agreeing to 2e-12) - the "exact" values quoted below;
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
#include "controllers/closed_loop.h"
#include "controllers/fractional_integrator.h"
#include "sim/linear/oustaloup.h"
#include "sim/linear/state_space.h"
#include "controllers/pid.h"
#include "controllers/reference_model.h"
#include "sim/base/numbers.h"

namespace ipmc {
namespace {

using ::ipmc::testing::ExpectThrowMentioning;
using ::ipmc::testing::LinearPid;
using ::ipmc::testing::WideBandIntegrator;

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
  // docs/VALIDATION.md, links 3/2/1: C_I 5.5 / 3.7 / 3.6 %; PID 9.0 / 20.3 /
  // 25.3 %, the earlier hand computation it quotes beside the exact values.
  // Measured at 1 kHz: C_I 5.6847 / 3.6920 / 3.6256, PID 9.0083 / 20.1365 /
  // 25.1778. The continuous loop gives PID 20.14 / 25.18 for links 2/1
  // (previous test), 0.16 and 0.12 below those rounded values; the
  // 1 kHz sampling adds 0.16 points to C_I on link 3. Tolerance 0.25
  // points against them.
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
  // J of eq. 11, link 3, horizons 2 / 5 / 10 s. docs/VALIDATION.md: 0.0868 / 0.1100
  // / 0.1421. Continuous (mpmath inverse Laplace, trapezoid on 2 ms):
  // 0.08678 / 0.11003 / 0.14211. Measured here: at 10 kHz 0.086793 /
  // 0.110033 / 0.142154 (tolerance 1e-4 against docs/VALIDATION.md: its rounding
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
