// The IPMC links' electrical power (sim/core/electrical.h): the network
// R_s + (R_p || C) under a zero-order hold against its closed forms, its
// energy balance, and the closed-loop run's report of <V I> per link.
#include "sim/core/electrical.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/core/scenario.h"
#include "sim/runs/closed_loop_run.h"

namespace ipmc::testing {
namespace {

// The paper's 10 mm x 3 mm link with the default values per area:
// R_s = 3.33 ohm, R_p = 333 ohm, C = 0.3 mF, tau = C (R_s || R_p) = 0.990 ms.
IpmcImpedance PaperLink() {
  return IpmcImpedance::ForArea(ElectricalConfig{}, 10e-3 * 3e-3);
}

// A step V0 from the uncharged state has the closed form (Laplace, or the
// first-order ODE dv/dt = (v_inf - v) / tau):
//   v(t) = v_inf (1 - e^(-t/tau)),  v_inf = V0 R_p / (R_s + R_p)
//   I(t) = V0 / (R_s + R_p) + V0 R_p / (R_s (R_s + R_p)) e^(-t/tau)
//   W_in(t) = V0 / (R_s + R_p) (V0 t + R_p / R_s V0 tau (1 - e^(-t/tau)))
// A constant voltage is its own zero-order hold, so any split of [0, t]
// into holds gives these to rounding.
TEST(ElectricalTest, AStepFollowsItsClosedFormWhateverTheHolds) {
  const double v0 = 3.0, t_end = 5e-3;
  for (const int holds : {1, 7, 100, 5000}) {
    IpmcImpedance link = PaperLink();
    const double rs = link.series_ohm(), rp = link.parallel_ohm(), tau = link.time_constant_s();
    double input_J = 0.0;
    for (int k = 0; k < holds; ++k) input_J += link.Hold(v0, t_end / holds).input_J;
    const double v_inf = v0 * rp / (rs + rp);
    const double decay = std::exp(-t_end / tau);
    EXPECT_NEAR(link.capacitor_voltage_V(), v_inf * (1.0 - decay), 1e-13 * v0) << holds;
    const double exact_J = v0 / (rs + rp) * (v0 * t_end + rp / rs * v0 * tau * (1.0 - decay));
    EXPECT_NEAR(input_J, exact_J, 1e-12 * exact_J) << holds;
  }
}

// Electrical energy in = dissipated in R_s and R_p + the change of the
// capacitor's energy, interval by interval, for any voltages and holds.
TEST(ElectricalTest, EnergyInIsDissipationPlusStoredEnergyToRounding) {
  IpmcImpedance link = PaperLink();
  double in_J = 0.0, out_J = 0.0, stored_J = 0.0;
  for (int k = 0; k < 2000; ++k) {
    const double voltage_V = 4.0 * std::sin(0.37 * k) + (k % 7 == 0 ? -2.5 : 0.5);
    const double hold_s = 1e-5 * (1 + k % 13) * (k % 97 == 0 ? 100.0 : 1.0);
    const double v_before = link.capacitor_voltage_V();
    const HoldEnergies w = link.Hold(voltage_V, hold_s);
    const double v_after = link.capacitor_voltage_V();
    EXPECT_NEAR(w.stored_change_J,
                0.5 * link.capacitance_F() * (v_after * v_after - v_before * v_before), 1e-18);
    EXPECT_GE(w.series_J, 0.0);
    EXPECT_GE(w.parallel_J, 0.0);
    // The energies at stake: the hold's and the capacitor's own, C v^2 / 2
    // (the stored change is a difference of two of those). Measured
    // residuals: at most 1.3e-15 of them.
    const double scale = std::abs(w.input_J) + w.series_J + w.parallel_J +
                         0.5 * link.capacitance_F() *
                             std::max(v_before * v_before, v_after * v_after);
    EXPECT_NEAR(w.input_J, w.series_J + w.parallel_J + w.stored_change_J, 1e-14 * scale) << k;
    in_J += w.input_J;
    out_J += w.series_J + w.parallel_J;
    stored_J += w.stored_change_J;
  }
  EXPECT_NEAR(in_J, out_J + stored_J, 1e-13 * in_J);
  EXPECT_NEAR(stored_J, 0.5 * link.capacitance_F() * std::pow(link.capacitor_voltage_V(), 2),
              1e-13 * in_J);
}

// The mean power of V0 sin(w t) into Z(w) = R_s + R_p / (1 + j w R_p C) is
// V0^2 / 2 Re(1 / Z(w)) in the steady state (phasors). The controller holds
// V0 sin(w t_k) over [t_k, t_k + h): with N = T / h holds a period the
// mean power over a steady period converges to it as 1 / N^2. At the
// corner w = 1 / tau, V0 = 2 V (0.302970 W), the relative errors (the
// test prints them) are
//   N       8       16       32       64       128      256
//   error  4.83e-2  1.25e-2  3.14e-3  7.87e-4  1.97e-4  4.92e-5
// (about 3.2 / N^2; docs/ENERGY.md).
TEST(ElectricalTest, SineMeanPowerConvergesToTheImpedancesAsTheHoldShrinks) {
  const IpmcImpedance reference = PaperLink();
  const double omega = 1.0 / reference.time_constant_s(), v0 = 2.0;
  const double exact_W = 0.5 * v0 * v0 * (1.0 / reference.Impedance_ohm(omega)).real();
  const double period_s = kTwoPi / omega;
  std::vector<double> errors;
  for (const int n : {8, 16, 32, 64, 128, 256}) {
    IpmcImpedance link = PaperLink();
    const double hold_s = period_s / n;
    double period_J = 0.0;
    for (int p = 0; p < 30; ++p) {  // tau is T / 6.3: 30 periods settle it
      period_J = 0.0;
      for (int k = 0; k < n; ++k) {
        period_J += link.Hold(v0 * std::sin(omega * (p * n + k) * hold_s), hold_s).input_J;
      }
    }
    errors.push_back((period_J / period_s - exact_W) / exact_W);
    std::printf("N = %3d holds a period: mean power %.6f W, relative error %.3g\n", n,
                period_J / period_s, errors.back());
  }
  for (size_t i = 0; i + 1 < errors.size(); ++i) {
    // Second order: each halving of the hold divides the error by 4.
    EXPECT_NEAR(errors[i] / errors[i + 1], 4.0, 0.15) << i;
  }
  EXPECT_NEAR(errors.front(), 4.83e-2, 1e-3);  // the table above
  EXPECT_LT(std::abs(errors.back()), 5e-4);     // 10x the measured 4.92e-5
}

TEST(ElectricalTest, ValuesArePerUnitAreaAndScaleWithTheElectrode) {
  ElectricalConfig config;
  const IpmcImpedance small = IpmcImpedance::ForArea(config, 1e-5);
  const IpmcImpedance large = IpmcImpedance::ForArea(config, 4e-5);
  EXPECT_DOUBLE_EQ(small.series_ohm(), 4.0 * large.series_ohm());
  EXPECT_DOUBLE_EQ(small.parallel_ohm(), 4.0 * large.parallel_ohm());
  EXPECT_DOUBLE_EQ(4.0 * small.capacitance_F(), large.capacitance_F());
  EXPECT_DOUBLE_EQ(small.time_constant_s(), large.time_constant_s());
  EXPECT_DOUBLE_EQ(small.series_ohm(), config.series_resistance_ohm_m2 / 1e-5);
}

TEST(ElectricalTest, BadValuesNameTheField) {
  const auto field_of = [](ElectricalConfig config) {
    try {
      config.Validate();
    } catch (const FieldError& error) {
      return error.field();
    }
    return std::string("none");
  };
  ElectricalConfig config;
  config.series_resistance_ohm_m2 = 0.0;
  EXPECT_EQ(field_of(config), "series_resistance_ohm_m2");
  config = {};
  config.parallel_resistance_ohm_m2 = -1.0;
  EXPECT_EQ(field_of(config), "parallel_resistance_ohm_m2");
  config = {};
  config.capacitance_F_m2 = std::nan("");
  EXPECT_EQ(field_of(config), "capacitance_F_m2");
  config = {};
  config.electrode_width_mm = 0.0;
  EXPECT_EQ(field_of(config), "electrode_width_mm");
  EXPECT_EQ(field_of(ElectricalConfig{}), "none");
}

// A short closed-loop run with the electrical model on: each link's mean
// electrical power is the held voltages (every controller sample, seen by
// the observer) replayed through the link's network, and the efficiency is
// the actuators' power over it.
TEST(ElectricalTest, TheRunReportsTheHeldVoltagesPowerPerLink) {
  ScenarioConfig scenario = ParseScenario(
      "model = \"../models/flagellum3.xml\"\ncycles = 2\ntimestep_s = 5e-4\n"
      "[waveform]\nfrequency_Hz = 2.0\n[electrical]\nenabled = true\n"
      "[output]\nsamples_per_cycle = 500\n",
      std::string(IPMC_SWIM_SOURCE_DIR) + "/scenarios/electrical.toml");
  std::vector<std::vector<double>> volts;
  const ClosedLoopResult result = SimulateScenario(
      scenario, [&](const mjModel*, const mjData*, const ClosedLoopSample& sample) {
        volts.push_back(sample.voltage_V);
      });
  const EnergyMetrics& energy = result.energy;
  ASSERT_TRUE(energy.electrical);
  ASSERT_EQ(energy.per_cycle.size(), 2u);
  ASSERT_EQ(volts.size(), 1000u);  // 500 samples of 1 ms per 0.5 s cycle, all recorded
  const double sample_s = 1e-3, period_s = 0.5;
  double total_W = 0.0;
  for (int q = 0; q < 3; ++q) {
    IpmcImpedance link = IpmcImpedance::ForArea(scenario.metrics.electrical, 10e-3 * 3e-3);
    std::vector<double> cycle_J(2, 0.0);
    for (size_t k = 0; k < volts.size(); ++k) {
      cycle_J[k / 500] += link.Hold(volts[k][q], sample_s).input_J;
    }
    for (int c = 0; c < 2; ++c) {
      EXPECT_NEAR(energy.per_cycle[c].electrical_power_W[q], cycle_J[c] / period_s,
                  1e-9 * cycle_J[c] / period_s)
          << "link " << q + 1 << " cycle " << c + 1;
    }
    EXPECT_GT(energy.electrical_power_W[q], 0.0);
    total_W += energy.electrical_power_W[q];
  }
  EXPECT_NEAR(energy.electrical_power_W_total, total_W, 1e-12 * total_W);
  EXPECT_DOUBLE_EQ(energy.electromechanical_efficiency,
                   energy.actuator_power_W_total / energy.electrical_power_W_total);
}

TEST(ElectricalTest, OffByDefaultWithNothingReported) {
  const ScenarioConfig scenario = ParseScenario(
      "model = \"../models/flagellum3.xml\"\ncycles = 1\n[waveform]\nfrequency_Hz = 2.0\n",
      std::string(IPMC_SWIM_SOURCE_DIR) + "/scenarios/electrical.toml");
  EXPECT_FALSE(scenario.metrics.electrical.enabled);
  const ClosedLoopResult result = SimulateScenario(scenario);
  EXPECT_FALSE(result.energy.electrical);
  EXPECT_TRUE(result.energy.electrical_power_W.empty());
  EXPECT_EQ(result.energy.electromechanical_efficiency, 0.0);
  EXPECT_EQ(ResolvedScenarioToml(scenario).find("electrical"), std::string::npos);
}

}  // namespace
}  // namespace ipmc::testing
