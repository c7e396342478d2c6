// The IPMC link models coupled to the clamped flagellum: the multibody
// follows the links' free deflection, single actuation drags the passive
// links along, and a clamped deflection is reported through MuJoCo's
// warnings.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <cstdio>

#include "ipmc_swim/ipmc_swim.h"
#include "sim/runs/bench_run.h"
#include "sim/linear/ipmc_link_model.h"
#include "tests/test_util.h"
#include "sim/base/numbers.h"

namespace ipmc::testing {
namespace {

// Fails on any MuJoCo warning the test does not expect.
class IpmcActuatorsTest : public MujocoWarnings {};

struct Phasor {
  double amplitude;
  double phase_rad;
};

// Least-squares fit of y = a sin(w t) + b cos(w t) + c + d t (the offset
// and drift absorb the slow start-up transient of the s^-0.5 factor).
Phasor FitSine(const std::vector<double>& t, const std::vector<double>& y, double w) {
  Eigen::MatrixXd basis(t.size(), 4);
  Eigen::VectorXd values(t.size());
  for (size_t i = 0; i < t.size(); ++i) {
    basis.row(i) << std::sin(w * t[i]), std::cos(w * t[i]), 1.0, t[i];
    values[i] = y[i];
  }
  const Eigen::Vector4d coef = basis.colPivHouseholderQr().solve(values);
  return {std::hypot(coef[0], coef[1]), std::atan2(coef[1], coef[0])};
}

// 1 V sine at w on link `driven` (1-based; 0: every link) of the model,
// recorded over the last `record_periods` of `periods`.
BenchRecord RunSine(const FlagellumSpec& spec, double w_rad_s, int driven, int periods,
                    int record_periods) {
  auto sim = MakeSimulation(spec);
  BenchSignal signal;
  signal.amplitude_V = 1.0;
  signal.frequency_Hz = w_rad_s / (2 * kPi);
  signal.duration_s = periods / signal.frequency_Hz;
  signal.driven_links = driven > 0 ? std::vector<int>{driven} : std::vector<int>{1, 2, 3};
  return RunBench(*sim, signal, (periods - record_periods) / signal.frequency_Hz);
}

TEST_F(IpmcActuatorsTest, ClampedLinksFollowTheirTransferFunctions) {
  FlagellumSpec spec;
  spec.clamped = true;
  spec.plants = "table2";  // each link its own Table 2 row
  for (double w : {0.5, 2.0, 10.0}) {
    for (int q = 0; q < 3; ++q) {
      const BenchRecord record = RunSine(spec, w, q + 1, w < 1.0 ? 6 : 12, 3);
      const Phasor measured = FitSine(record.t_s, record.relative_mm[q], w);
      const std::complex<double> expected =
          LinkResponseExact(PaperLinkParams(q + 1, IpmcModelKind::kG1), w);
      const double gain_error = measured.amplitude / std::abs(expected) - 1.0;
      double phase_error_deg = (measured.phase_rad - std::arg(expected)) * 180 / kPi;
      phase_error_deg -= 360.0 * std::round(phase_error_deg / 360.0);
      std::printf("w %5.1f rad/s link %d: |y| %.5f mm vs |P| %.5f mm (%+.2f %%), phase %+.2f deg\n",
                  w, q + 1, measured.amplitude, std::abs(expected), 100 * gain_error,
                  phase_error_deg);
      // Driven alone, each link follows P_q within the measured 0.41 % /
      // 0.68 deg up to 2 rad/s; the gap grows with frequency (the hinge's
      // first-order lag c/k = 3.2 ms, the 1 kHz hold and the drag: 1.3 % /
      // 2.1 deg at 10 rad/s) - see the table in docs/MODEL.md,
      // "IPMC actuators".
      EXPECT_LT(std::abs(gain_error), w < 5.0 ? 0.02 : 0.05);
      EXPECT_LT(std::abs(phase_error_deg), w < 5.0 ? 2.0 : 5.0);
    }
  }
}

// The bench model's 0.5 ms step (models/flagellum3_clamped.xml) against
// half of it, at the top of the identification band (50 rad/s) and below,
// each link driven alone: the recorded relative deflection's amplitude and
// phase (the bench records the state at the sample time, so the step
// enters only through the integration): first order, the held moment's
// delay of h / 2.
TEST_F(IpmcActuatorsTest, BenchRecordConvergesOnHalvingTheStep) {
  FlagellumSpec spec;
  spec.clamped = true;
  spec.plants = "table2";
  for (double w : {10.0, 50.0}) {
    for (int q = 0; q < 3; ++q) {
      Phasor at[2];
      for (int half = 0; half < 2; ++half) {
        spec.timestep_s = half ? 2.5e-4 : 5e-4;
        const BenchRecord record = RunSine(spec, w, q + 1, 12, 3);
        at[half] = FitSine(record.t_s, record.relative_mm[q], w);
      }
      const double gain_change = at[0].amplitude / at[1].amplitude - 1.0;
      const double phase_change_deg = (at[0].phase_rad - at[1].phase_rad) * 180 / kPi;
      std::printf("w %4.1f rad/s link %d: 0.5 ms against 0.25 ms: gain %+.2e, phase %+.2e deg\n", w,
                  q + 1, gain_change, phase_change_deg);
      // The step damps the rigid links' hinges with c_eff and holds the
      // active moment over the step (plugin/dynamics/step_model.h), whose
      // exact relaxation of the massless hinge lags the moment by h / 2:
      // halving the step takes w (h - h / 2) / 2 off the phase lag (0.072
      // deg at 10 rad/s, 0.358 deg at 50 rad/s). Measured: 1.04-1.05 of it
      // at 10 rad/s, 1.05-1.29 at 50 rad/s (the drag and the inertia add
      // the rest); the gain moves by at most 5e-4. Gain: the 0.5 % asked
      // of halving; phase: the delay's share within 0.35.
      const double delay_deg = w * (5e-4 - 2.5e-4) / 2 * 180 / kPi;
      EXPECT_LT(std::abs(gain_change), 0.005);
      EXPECT_NEAR(-phase_change_deg / delay_deg, 1.0, 0.35);
    }
  }
}

TEST_F(IpmcActuatorsTest, SingleActuationMovesThePassiveLinksWithLinkOne) {
  FlagellumSpec spec;
  spec.clamped = true;
  spec.actuation = "single";
  const double w = 2.0;
  const BenchRecord record = RunSine(spec, w, 1, 12, 4);
  const Phasor tip1 = FitSine(record.t_s, record.tip_lateral_mm[0], w);
  const Phasor tip2 = FitSine(record.t_s, record.tip_lateral_mm[1], w);
  const Phasor tip3 = FitSine(record.t_s, record.tip_lateral_mm[2], w);
  // Section 4.3: K2 = tip 2 / tip 1, K3 = tip 3 / tip 2.
  const double k2 = tip2.amplitude / tip1.amplitude, k3 = tip3.amplitude / tip2.amplitude;
  const double lag3_deg = (tip1.phase_rad - tip3.phase_rad) * 180 / kPi;
  std::printf("single actuation at %.1f rad/s: K2 = %.3f, K3 = %.3f, tip 3 lag %.2f deg "
              "(paper: 3.72, 7.37, 4 deg)\n", w, k2, k3, lag3_deg);
  // The passive links are rigid and their hinges stiff against the small
  // drag at 2 rad/s, so they turn with link 1 as one straight body: the
  // tips move in proportion to their distance from the clamp,
  // K2 = 20.5 / 10 = 2.05, K3 = 31 / 20.5 = 1.512, with no lag. The
  // paper's larger 3.72 / 7.37 and its 4 deg need the strip to bend along
  // its links (tests/flexible_link_test.cc: an arc gives 3.10 / 1.68).
  EXPECT_NEAR(k2, 2.05, 0.01);
  EXPECT_NEAR(k3, 31.0 / 20.5, 0.01);
  EXPECT_LT(std::abs(lag3_deg), 0.5);
}

// 50 V held on link 1 of the clamped flagellum: the s^-0.5 factor grows
// the free deflection a0 V 2 sqrt(t / pi) past the 10 mm link's reach
// after about 0.2 s (a0 = 0.376 mm/V). The clamp is reported through
// mju_warning, once.
TEST_F(IpmcActuatorsTest, ClampedDeflectionWarnsOnceThroughMujoco) {
  ExpectWarning("exceeds the link's reach", 1);
  FlagellumSpec spec;
  spec.clamped = true;
  auto sim = MakeSimulation(spec);
  mjModel* m = sim->model();
  mjData* d = sim->data();
  const double volts[3] = {50.0, 0.0, 0.0};
  SetVoltages(d, volts, 3);
  for (int step = 0; step < 20000 && ClampCount(d) < 10; ++step) mj_step(m, d);
  EXPECT_GE(ClampCount(d), 10);
  EXPECT_EQ(Count("exceeds the link's reach"), 1);  // the first clamp only
  EXPECT_EQ(Count("ipmc link 1:"), 1);
  for (const std::string& warning : Received()) std::printf("warning: %s\n", warning.c_str());
}

}  // namespace
}  // namespace ipmc::testing
