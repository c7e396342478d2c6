// Two models with different fluids stepped in two threads give exactly the
// numbers of stepping them one after the other: the callbacks dispatch to
// per-data contexts and share no mutable state.
#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "tests/test_util.h"

namespace ipmc::testing {
namespace {

// Fails on any MuJoCo warning the test does not expect.
class ParallelTest : public MujocoWarnings {};

std::vector<double> RunWave(double viscosity_Pa_s) {
  FlagellumSpec spec;
  spec.viscosity_Pa_s = viscosity_Pa_s;
  spec.timestep_s = 2e-4;
  auto sim = MakeSimulation(spec);
  const auto gait = MakeSineGait(TravellingWave(3, 0.5, 0.3, 2.0));
  GaitRunOptions options;
  options.cycles = 1;
  const GaitRunResult result = RunGait(*sim, *gait, options);
  std::vector<double> trace;
  for (const GaitSample& s : result.samples) {
    trace.push_back(s.pose.com_x_mm);
    trace.push_back(s.pose.com_y_mm);
    trace.push_back(s.pose.yaw_rad);
  }
  return trace;
}

TEST_F(ParallelTest, TwoViscositiesInTwoThreadsMatchSequentialRuns) {
  const std::vector<double> water_alone = RunWave(1e-3);
  const std::vector<double> glycerol_alone = RunWave(1.0);
  ASSERT_NE(water_alone, glycerol_alone);  // the fluids really differ

  std::vector<double> water, glycerol;
  std::thread a([&] { water = RunWave(1e-3); });
  std::thread b([&] { glycerol = RunWave(1.0); });
  a.join();
  b.join();
  EXPECT_EQ(water, water_alone);        // bit for bit
  EXPECT_EQ(glycerol, glycerol_alone);
}

}  // namespace
}  // namespace ipmc::testing
