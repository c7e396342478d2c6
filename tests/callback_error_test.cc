// No C++ exception crosses a MuJoCo callback (ipmc_swim.h, "Callbacks"):
// a failure inside mjcb_control is recorded for the data, reported through
// mju_warning and returned by ipmc::LastError; Simulation::Step turns it
// into its one-line error. A host that replaces the callbacks after Attach
// is warned once.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "ipmc_swim/ipmc_swim.h"
#include "sim/core/simulation.h"
#include "tests/test_util.h"

namespace ipmc::testing {
namespace {

class CallbackErrorTest : public MujocoWarnings {};

const std::string kClamped = std::string(IPMC_SWIM_SOURCE_DIR) + "/models/flagellum3_clamped.xml";

// An infinite d->time makes the actuators refuse to advance, by throwing,
// inside mjcb_control (here run by mj_forward).
TEST_F(CallbackErrorTest, ActuatorFailureIsRecordedNotThrownThroughMuJoCo) {
  ExpectWarning("ipmc_swim: ipmc actuators: d->time is infinite");
  Simulation sim(LoadModelFile(kClamped), kClamped);
  EXPECT_STREQ(LastError(sim.data()), "");
  const double volts[3] = {1.0, 1.0, 1.0};
  SetVoltages(sim.data(), volts, 3);
  sim.data()->time = INFINITY;
  mj_forward(sim.model(), sim.data());
  EXPECT_STREQ(LastError(sim.data()), "ipmc actuators: d->time is infinite (it must be finite)");
  EXPECT_FALSE(ipmc::Step(sim.model(), sim.data()));
  EXPECT_STREQ(LastError(sim.data()), "d->time is infinite (it must be finite)");
  try {
    sim.Step();
    ADD_FAILURE() << "Simulation::Step did not throw";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(kClamped + ": d->time is infinite (it must be finite)"),
              std::string::npos)
        << message;
  }
}

TEST_F(CallbackErrorTest, ReplacedControlCallbackIsReportedOnce) {
  ExpectWarning("mjcb_control was replaced after ipmc::Attach");
  Simulation sim(LoadModelFile(kClamped), kClamped);
  const mjfGeneric ours = mjcb_control;
  mjcb_control = nullptr;
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(ipmc::Step(sim.model(), sim.data()));
  mjcb_control = ours;
  EXPECT_EQ(Count("mjcb_control was replaced"), 1);
  EXPECT_TRUE(ipmc::Step(sim.model(), sim.data()));
}

}  // namespace
}  // namespace ipmc::testing
