// RFT calibrated on the flat plates, fitted (`fluid.rft_coefficients =
// "ribbon_fitted"`), against the plates' swim and fluid power in the
// paper's default job. The calibration against the plate model itself:
// plugin/tests/ribbon_plate_calibration_test.cc.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "ipmc_swim/fields.h"
#include "sim/core/scenario.h"
#include "sim/runs/closed_loop_run.h"

namespace ipmc::testing {
namespace {

const std::string kPaper = std::string(IPMC_SWIM_SOURCE_DIR) + "/scenarios/paper.toml";

// The paper's default job (three 100 s cycles), cycle 3, against the plates
// extrapolated in 1 / k from k = 4 and 5 (docs/FLUIDS.md, "Flat plates":
// 0.828894 mm and 1.59463e-12 W, themselves uncertain by about 0.5 % and
// 1 %, the distance to the extrapolations from k = 3 and 4 and from k = 5
// and 6: +0.48 % / -1.2 % and +0.42 % / -0.97 %). The factors were fitted
// to two figures to the same reference with the plates' cached resistance
// alone (0.830256 mm, 1.59466e-12 W); against today's they leave +0.37 %
// in the swim and -0.21 % in the power. 2 % is five times that (and four
// times the reference's own 0.5 %): a change in the calibration or the
// dynamics that moves the swim fails it.
TEST(RibbonCoefficientsTest, FittedSetSwimsAsThePlatesInThePaperRun) {
  constexpr double kPlatesSwim_mm = 0.828894, kPlatesFluidPower_W = 1.59463e-12;
  ScenarioConfig scenario = LoadScenario(kPaper);
  scenario.fluid.rft_coefficients = CoefficientModel::kRibbonFitted;
  const ClosedLoopResult result = SimulateScenario(scenario);
  const double swim_mm = result.swim.per_cycle.at(2).com_along;
  const double power_W = result.energy.per_cycle.at(2).fluid_power_W;
  std::printf("ribbon_fitted, default job, cycle 3: %.6g mm (plates %.6g), %.6g W (plates %.6g)\n",
              swim_mm, kPlatesSwim_mm, power_W, kPlatesFluidPower_W);
  EXPECT_NEAR(swim_mm / kPlatesSwim_mm, 1.0, 0.02);
  EXPECT_NEAR(power_W / kPlatesFluidPower_W, 1.0, 0.02);
}

}  // namespace
}  // namespace ipmc::testing
