// Physics checks of RFT swimming in the kinematic (prescribed-gait) mode.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>

#include "tests/test_util.h"
#include "sim/base/numbers.h"

namespace ipmc::testing {
namespace {


// Net displacement of the centre of mass along the swimming axis in the
// second cycle (the first includes the start from rest) [mm].
double SecondCycleAlong_mm(const FlagellumSpec& spec, const Gait& gait) {
  return RunGaitOn(spec, gait, 2).swim.per_cycle[1].com_along;
}

SineGaitConfig ChainWave(int joints, double frequency_Hz, double amplitude_rad,
                         double phase_lag_rad) {
  return TravellingWave(joints, frequency_Hz, amplitude_rad, phase_lag_rad);
}

TEST(SwimmingTest, ReciprocalStrokeGivesNoNetDisplacement) {
  FlagellumSpec spec = StokesChain(6, 30.0);
  // All joints in phase: the stroke retraces itself (scallop theorem).
  const auto reciprocal = MakeSineGait(ChainWave(5, kStokesFrequency_Hz, 0.4, 0.0));
  const auto wave = MakeSineGait(ChainWave(5, kStokesFrequency_Hz, 0.4, 1.0));
  const double moving_mm = SecondCycleAlong_mm(spec, *wave);
  const Displacement_mm coarse = RunGaitOn(spec, *reciprocal, 2).swim.per_cycle[1];
  spec.timestep_s *= 0.5;
  const Displacement_mm fine = RunGaitOn(spec, *reciprocal, 2).swim.per_cycle[1];
  std::printf("travelling wave %.4f mm per cycle; reciprocal: %.3e mm (dt 1 ms), %.3e mm (0.5 ms)\n",
              moving_mm, coarse.com_along, fine.com_along);
  EXPECT_GT(moving_mm, 0.1);
  // Measured: 1.7e-3 of the travelling wave's displacement at dt = 1 ms,
  // halving with the step: a first-order time-discretisation residual
  // that vanishes as dt -> 0 (the body's inertia, omega tau = 3.6e-3, does
  // not show at this level).
  EXPECT_LT(std::abs(coarse.com_along), 2e-2 * moving_mm);
  EXPECT_LT(std::abs(coarse.com_across), 2e-2 * moving_mm);
  EXPECT_NEAR(coarse.com_along / fine.com_along, 2.0, 0.1);
}

TEST(SwimmingTest, ReversingTheWaveReversesTheSwim) {
  const FlagellumSpec spec = StokesChain(6, 30.0);
  const auto forward = MakeSineGait(ChainWave(5, kStokesFrequency_Hz, 0.4, 1.0));
  const auto backward = MakeSineGait(ChainWave(5, kStokesFrequency_Hz, 0.4, -1.0));
  const GaitRunResult forward_run = RunGaitOn(spec, *forward, 2);
  const double forward_mm = forward_run.swim.per_cycle[1].com_along;
  const double backward_mm = SecondCycleAlong_mm(spec, *backward);
  // The servo holds the gait: measured max error 5.0e-5 rad on 0.4 rad
  // references (1.3e-4 relative), so these checks measure the fluid
  // model, not the servo.
  EXPECT_LT(forward_run.max_tracking_error_rad, 5e-4);
  std::printf("forward %.6f mm, backward %.6f mm per cycle, servo error %.2e rad\n", forward_mm,
              backward_mm, forward_run.max_tracking_error_rad);
  EXPECT_GT(forward_mm, 0.1);
  // The backward wave is the time reversal of the mirrored forward wave,
  // so in Stokes flow the two cancel; measured |sum| = 2.7e-4 |forward|
  // (first order in dt, as for the reciprocal stroke).
  EXPECT_NEAR(forward_mm + backward_mm, 0.0, 3e-3 * forward_mm);
}

TEST(SwimmingTest, StokesLimitDisplacementIndependentOfFrequencyAndViscosity) {
  FlagellumSpec spec = StokesChain(6, 30.0);
  const auto base = MakeSineGait(ChainWave(5, kStokesFrequency_Hz, 0.4, 1.0));
  const double base_mm = SecondCycleAlong_mm(spec, *base);

  const auto slow = MakeSineGait(ChainWave(5, 0.5 * kStokesFrequency_Hz, 0.4, 1.0));
  const double slow_mm = SecondCycleAlong_mm(spec, *slow);

  FlagellumSpec viscous = spec;
  viscous.viscosity_Pa_s *= 2.0;
  const double viscous_mm = SecondCycleAlong_mm(viscous, *base);
  std::printf("per cycle: base %.7f, half frequency %.7f, double viscosity %.7f mm\n", base_mm,
              slow_mm, viscous_mm);
  // Residuals are O(omega tau) = 3.6e-3 effects of the body's inertia.
  EXPECT_NEAR(slow_mm / base_mm, 1.0, 1e-3);
  EXPECT_NEAR(viscous_mm / base_mm, 1.0, 1e-3);
}

// Gray & Hancock (1955), Lighthill (1975): an infinite filament carrying
// y = b sin(k x - w t) swims at U = (xi_n / xi_t - 1) (b k)^2 c / 2,
// c = w / k, to second order in b k. Per cycle: (xi_n/xi_t - 1)(bk)^2 lambda/2.
// A finite free swimmer recoils sideways and in yaw, which slows it by a
// few percent, less with more wavelengths on the body.
TEST(SwimmingTest, ManyLinkChainMatchesClassicalRftSpeed) {
  constexpr int kLinks = 48;
  constexpr double kLength_mm = 32.0;
  constexpr double kBk = 0.1;
  // Gray & Hancock's coefficients of the generator's strip (mu = 1e-3 Pa s,
  // a = 0.8125 mm, lambda = 32 mm): xi_n = 4 pi mu / (ln(2 lambda / a) + 1/2),
  // xi_t = 2 pi mu / (ln(2 lambda / a) - 1/2), so xi_n / xi_t =
  // 2 (ln(2 lambda / a) - 1/2) / (ln(2 lambda / a) + 1/2).
  const double log_term = std::log(2 * 32e-3 / 0.8125e-3);
  const double xi_ratio = 2 * (log_term - 0.5) / (log_term + 0.5);
  double previous_error = 1.0;
  for (double waves : {2.0, 4.0}) {
    FlagellumSpec spec = StokesChain(kLinks, kLength_mm);
    spec.timestep_s = 2.5e-3;
    const double lambda_mm = kLength_mm / waves;
    const double k_per_mm = 2.0 * kPi / lambda_mm;
    const double dx_mm = kLength_mm / kLinks;
    // Joint angle = curvature x link length: y'' = -b k^2 sin(k x - w t).
    const double amplitude_rad = kBk * k_per_mm * dx_mm;
    const auto gait =
        MakeSineGait(ChainWave(kLinks - 1, kStokesFrequency_Hz, amplitude_rad, k_per_mm * dx_mm));
    const double measured_mm = SecondCycleAlong_mm(spec, *gait);
    const double classical_mm =
        0.5 * (xi_ratio - 1.0) * kBk * kBk * lambda_mm;
    const double error = std::abs(measured_mm / classical_mm - 1.0);
    std::printf("%.0f wavelengths: %.6f mm per cycle, classical %.6f mm, error %.2f %%\n", waves,
                measured_mm, classical_mm, 100 * error);
    EXPECT_LT(error, previous_error);  // recoil fades with more wavelengths
    previous_error = error;
  }
  // Measured: 9.0 % at two wavelengths, 3.6 % at four.
  EXPECT_LT(previous_error, 0.05);
}

TEST(SwimmingTest, PurcellSquareStrokeSwimsAndCsvGaitReproducesIt) {
  const FlagellumSpec spec = StokesChain(3, 30.0);
  SquareStrokeConfig square;
  square.frequency_Hz = kStokesFrequency_Hz;
  square.amplitude_rad = 0.8;
  square.joints = 2;
  const auto stroke = MakeSquareStroke(square);
  const double square_mm = SecondCycleAlong_mm(spec, *stroke);

  // The same stroke sampled into a CSV file, 2000 rows per cycle.
  const std::string path = ::testing::TempDir() + "purcell_stroke.csv";
  {
    std::ofstream csv(path);
    csv << "time_s,q1_rad,q2_rad\n";
    csv << std::setprecision(17);
    for (int i = 0; i <= 2000; ++i) {
      const double t = i * stroke->Period_s() / 2000;
      const JointReference ref = stroke->At(t);
      csv << t << "," << ref.angle_rad[0] << "," << ref.angle_rad[1] << "\n";
    }
  }
  const auto from_csv = LoadCsvGait(path, 2);
  std::remove(path.c_str());
  EXPECT_DOUBLE_EQ(from_csv->Period_s(), stroke->Period_s());
  const double csv_mm = SecondCycleAlong_mm(spec, *from_csv);
  std::printf("Purcell square stroke: %.6f mm per cycle, from CSV %.6f mm\n", square_mm, csv_mm);
  EXPECT_GT(std::abs(square_mm), 0.1);
  // Linear interpolation of 2000 samples: measured difference 1.5e-5.
  EXPECT_NEAR(csv_mm / square_mm, 1.0, 2e-4);
}

TEST(SwimmingTest, HalvingTheTimeStepChangesDisplacementByLessThanHalfAPercent) {
  // The paper's flagellum (models/flagellum3.xml defaults) at the paper's
  // 0.01 Hz, one cycle, default step 1e-4 s against 5e-5 s.
  FlagellumSpec spec;
  const auto gait = MakeSineGait(TravellingWave(3, 0.01, 0.3, 2.0));
  const double default_mm = RunGaitOn(spec, *gait, 1).swim.per_cycle[0].com_along;
  spec.timestep_s *= 0.5;
  const double half_mm = RunGaitOn(spec, *gait, 1).swim.per_cycle[0].com_along;
  std::printf("one cycle: dt 1e-4 s %.7f mm, dt 5e-5 s %.7f mm\n", default_mm, half_mm);
  EXPECT_LT(std::abs(default_mm / half_mm - 1.0), 0.005);
}

}  // namespace
}  // namespace ipmc::testing
