// RFT coefficients that follow the scenario: the Gray-Hancock and Lighthill
// coefficients take the scenario's wavelength (fluid.rft_wavelength_mm, or
// else the wave's), fluid.rft_coefficients picks the set, and a run warns
// when the Reynolds number approaches 1 or the wave is too short for the
// drag segments.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "ipmc_swim/fields.h"
#include "ipmc_swim/ipmc_swim.h"
#include "sim/base/numbers.h"
#include "sim/core/scenario.h"
#include "sim/core/simulation.h"
#include "sim/core/swim_meter.h"
#include "sim/runs/closed_loop_run.h"
#include "tests/test_util.h"

namespace ipmc::testing {
namespace {

const std::string kPaper = std::string(IPMC_SWIM_SOURCE_DIR) + "/scenarios/paper.toml";

ScenarioConfig PaperWith(const std::string& extra) {
  return ParseScenario("model = \"../models/flagellum3.xml\"\n" + extra, kPaper);
}

// The RFT drag the scenario's simulation attaches: the fields of its model
// (the scenario's settings written into them) and the normal coefficient
// the coupling took from them, the drag of the straight body (qpos0)
// towed broadside (root_y) over its length, sum xi_n L / sum L.
struct AttachedDrag {
  CoefficientModel model = CoefficientModel::kGrayHancock;
  double wavelength_m = 0.0;
  double wall_distance_m = 0.0;
  double normal_N_s_m2 = 0.0;
};
AttachedDrag DragOf(const ScenarioConfig& scenario) {
  const std::unique_ptr<Simulation> sim = LoadScenarioSimulation(scenario);
  const mjModel* m = sim->model();
  AttachedDrag drag;
  drag.model =
      ParseCoefficientModel(FindCustomText(m, kAttrCoefficients).value_or("gray_hancock"));
  drag.wavelength_m = FindCustomScalar(m, kAttrWavelength).value_or(0.0);
  drag.wall_distance_m = FindCustomScalar(m, kAttrWallDistance).value_or(0.0);
  double length_m = 0.0;
  for (double segment_m : FluidOf(sim->data()).segment_length_m) length_m += segment_m;
  const int root_y = m->jnt_dofadr[mj_name2id(m, mjOBJ_JOINT, "root_y")];
  drag.normal_N_s_m2 = DragMatrix(m, sim->data())[(m->nv + 1) * root_y] / length_m;
  return drag;
}

TEST(RftScenarioTest, CoefficientsFollowTheWavelength) {
  // The model file says 32 mm; the wave of 16 mm wins unless the scenario
  // names the coefficients' wavelength itself.
  EXPECT_DOUBLE_EQ(DragOf(PaperWith("")).wavelength_m, 0.032);
  const AttachedDrag wave = DragOf(PaperWith("[waveform]\nwavelength_mm = 16.0\n"));
  EXPECT_DOUBLE_EQ(wave.wavelength_m, 0.016);
  EXPECT_EQ(wave.model, CoefficientModel::kGrayHancock);
  // Gray & Hancock (1955): xi_n = 4 pi mu / (ln(2 lambda / a) + 1/2), the
  // model's mu = 1e-3 Pa s and a = 0.8125 mm, lambda = 16 mm. The sum over
  // the segments rounds: 1e-12.
  const double expected_N_s_m2 = 4 * kPi * 1e-3 / (std::log(2 * 0.016 / 0.8125e-3) + 0.5);
  EXPECT_NEAR(wave.normal_N_s_m2 / expected_N_s_m2, 1.0, 1e-12);
  const AttachedDrag given =
      DragOf(PaperWith("[waveform]\nwavelength_mm = 16.0\n[fluid]\nrft_wavelength_mm = 40.0\n"));
  EXPECT_DOUBLE_EQ(given.wavelength_m, 0.040);
}

TEST(RftScenarioTest, CoefficientSetIsAScenarioKey) {
  const AttachedDrag lighthill = DragOf(PaperWith("[fluid]\nrft_coefficients = \"lighthill\"\n"));
  EXPECT_EQ(lighthill.model, CoefficientModel::kLighthill);
  ExpectThrowMentioning<std::runtime_error>(
      [] { PaperWith("[fluid]\nrft_coefficients = \"direct\"\n"); }, "fluid.rft_coefficients");
  ExpectThrowMentioning<std::runtime_error>(
      [] { PaperWith("[fluid]\nrft_wavelength_mm = 0\n"); }, "fluid.rft_wavelength_mm");
}

TEST(RftScenarioTest, WarnsOnReynoldsNumberAndShortWaves) {
  SwimMetrics swim;
  swim.longest_segment_mm = 10.0;
  swim.reynolds_tip = 0.789;                        // the paper run's: inside Re < 1
  EXPECT_TRUE(FluidWarnings(swim, 32.0).empty());  // 3.2 segments per wavelength
  swim.reynolds_tip = 1.18;                         // 0.015 Hz (docs/RUNS.md, Sweeps)
  swim.frequency_Hz = 0.015;
  swim.viscosity_Pa_s = 1e-3;
  const std::vector<std::string> reynolds = FluidWarnings(swim, 32.0);
  ASSERT_EQ(reynolds.size(), 1u);
  EXPECT_NE(reynolds[0].find("Reynolds numbers 1.18 (tip)"), std::string::npos) << reynolds[0];
  // Every Reynolds number goes as rho f / mu: Re = 0.1 at 11.8 times the
  // viscosity, or at 1 / 11.8 of the frequency.
  EXPECT_NE(reynolds[0].find("a viscosity of 0.0118 Pa s at 0.015 Hz, or 0.00127 Hz in this "
                             "liquid"),
            std::string::npos)
      << reynolds[0];
  EXPECT_EQ(reynolds[0].find("sphere"), std::string::npos) << reynolds[0];  // no Oseen past 1
  swim.reynolds_tip = 0.1;
  swim.reynolds_oscillatory = 14.1;  // a 3 mm strip at 1 Hz in water (Sader 1998)
  EXPECT_EQ(FluidWarnings(swim, 32.0).size(), 1u);
  swim.reynolds_oscillatory = 0.0;
  swim.reynolds_tip = 0.1;
  const std::vector<std::string> short_wave = FluidWarnings(swim, 16.0);
  ASSERT_EQ(short_wave.size(), 1u);
  EXPECT_NE(short_wave[0].find("spans 1.6 drag segments of 10 mm"), std::string::npos)
      << short_wave[0];
  EXPECT_TRUE(FluidWarnings(swim, 0.0).empty());  // no wave: no resolution check
}

TEST(RftScenarioTest, ARunCarriesItsWarnings) {
  // The example: a 16 mm wave on 10 mm links is under-resolved.
  ScenarioConfig scenario =
      PaperWith("cycles = 1\ntimestep_s = 1e-3\n[waveform]\nwavelength_mm = 16.0\n"
                "frequency_Hz = 0.5\n");
  scenario.model.dynamics = Dynamics::kStokes;
  const ClosedLoopResult result = SimulateScenario(scenario);
  bool resolution = false;
  for (const std::string& warning : result.swim.warnings) {
    resolution = resolution || warning.find("drag segments") != std::string::npos;
  }
  EXPECT_TRUE(resolution);
  EXPECT_DOUBLE_EQ(result.swim.longest_segment_mm, 10.0);
}


// fluid.wall_gap_mm gives the near-wall coefficients (checked against
// Katz, Blake & Paveri-Fontana 1975 in near_wall_rft_test.cc) for the
// centreline's distance from the wall.
TEST(RftScenarioTest, WallGapGivesNearWallCoefficients) {
  // Katz, Blake & Paveri-Fontana: xi_n = 4 pi mu / ln(2 h / a), parallel
  // to the wall.
  const double wall_normal_N_s_m2 = 4 * kPi * 1e-3 / std::log(2 * 2.5e-3 / 0.8125e-3);
  // A 1 mm gap below the 3 mm strip puts the centreline 2.5 mm above it.
  const AttachedDrag config = DragOf(PaperWith("[fluid]\nwall_gap_mm = 1.0\n"));
  EXPECT_EQ(config.model, CoefficientModel::kNearWall);
  EXPECT_DOUBLE_EQ(config.wall_distance_m, 2.5e-3);
  EXPECT_NEAR(config.normal_N_s_m2, wall_normal_N_s_m2, 1e-12);
  ExpectThrowMentioning<std::runtime_error>([] { PaperWith("[fluid]\nwall_gap_mm = -1\n"); },
                                            "fluid.wall_gap_mm");
  ExpectThrowMentioning<std::runtime_error>(
      [] {
        LoadScenarioSimulation(
            PaperWith("[fluid]\nwall_gap_mm = 1.0\nrft_coefficients = \"lighthill\"\n"));
      },
      "exclude each other");
}

// The wall changes the swim: 2 mm from it the coefficients are larger
// and their ratio is 2.
TEST(RftScenarioTest, TheWallChangesTheSwim) {
  ScenarioConfig free =
      PaperWith("cycles = 1\ntimestep_s = 1e-3\n[waveform]\nfrequency_Hz = 0.5\n");
  free.model.dynamics = Dynamics::kStokes;
  ScenarioConfig wall = free;
  wall.fluid.wall_gap_mm = 2.0;
  const double free_mm = SimulateScenario(free).swim.per_cycle.at(0).com_along;
  const double wall_mm = SimulateScenario(wall).swim.per_cycle.at(0).com_along;
  std::printf("per cycle: free %.6g mm, 2 mm from a wall %.6g mm\n", free_mm, wall_mm);
  EXPECT_GT(std::abs(wall_mm / free_mm - 1.0), 0.01);
}

}  // namespace
}  // namespace ipmc::testing
