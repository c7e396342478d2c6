// The coupling's state lives in mjData.userdata (ipmc_swim.h, "State"), so
// MuJoCo's own functions act on it: mj_copyData into an attached mjData
// branches a run that continues bit for bit, in both dynamics and every
// fluid model (a dense one recomputing its resistance at every
// evaluation); mj_resetData starts the actuators from rest; a copy that is
// not attached, a model without room for the state, and a huge velocity
// are refused.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <iomanip>
#include <string>
#include <vector>

#include "ipmc_swim/ipmc_swim.h"
#include "tests/test_util.h"

namespace ipmc::testing {
namespace {

class StateInDataTest : public MujocoWarnings {};

constexpr int kLinks = 3;

// The paper's free flagellum with two sub-segments per link (each step's
// curvature starts Newton from the last one, part of the state) in
// `dynamics`, with `fluid` and its settings as <custom> fields. A dense
// fluid recomputes its resistance at every evaluation (shape tolerance 0):
// its cache within the tolerance is the coupling's own, not mjData's.
ModelPtr Flagellum(const std::string& dynamics, const std::string& fluid) {
  FlagellumSpec spec;
  spec.segments_per_link = 2;
  std::string custom = "    <text name=\"ipmc_dynamics\" data=\"" + dynamics + "\"/>\n" +
                       "    <text name=\"ipmc_fluid_model\" data=\"" + fluid + "\"/>\n";
  if (fluid == "stokeslets" || fluid == "plates") {
    const std::string prefix = fluid == "plates" ? "plate" : "stokeslet";
    custom += "    <numeric name=\"ipmc_fluid_" + prefix +
              "_shape_tolerance_rad\" data=\"0\"/>\n";
  }
  std::string xml = GenerateFlagellumMjcf(spec);
  xml.insert(xml.find("  </custom>"), custom);
  return LoadModelString(xml);
}

// An mjData attached for its lifetime.
struct AttachedData {
  explicit AttachedData(const mjModel* m) : d(mj_makeData(m)) { EXPECT_TRUE(Attach(m, d.get())); }
  ~AttachedData() { Detach(d.get()); }
  mjData* get() const { return d.get(); }
  DataPtr d;
};

// Steps [first, first + count) of distinct sines on the three links,
// changed every 10 steps; qpos and qvel after each step.
std::vector<double> Drive(const mjModel* m, mjData* d, int first, int count) {
  std::vector<double> trace;
  for (int step = first; step < first + count; ++step) {
    if (step % 10 == 0) {
      const double t_s = step * m->opt.timestep;
      const double volts[kLinks] = {3.0 * std::sin(31.4 * t_s), -2.0 * std::cos(44.0 * t_s),
                                    1.5 * std::sin(69.1 * t_s + 0.3)};
      SetVoltages(d, volts, kLinks);
    }
    EXPECT_TRUE(Step(m, d)) << LastError(d);
    trace.insert(trace.end(), d->qpos, d->qpos + m->nq);
    trace.insert(trace.end(), d->qvel, d->qvel + m->nv);
  }
  return trace;
}

double LargestDifference(const std::vector<double>& a, const std::vector<double>& b) {
  double largest = 0;
  for (size_t i = 0; i < a.size(); ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
  return largest;
}

struct Case {
  const char* dynamics;
  const char* fluid;
};

class BranchTest : public StateInDataTest, public ::testing::WithParamInterface<Case> {};

// A branch made with mj_copyData into an mjData attached before, or
// attached after the copy, continues bit for bit as the original.
TEST_P(BranchTest, CopyIntoAttachedDataContinuesBitIdentically) {
  const ModelPtr m = Flagellum(GetParam().dynamics, GetParam().fluid);
  AttachedData original(m.get());
  Drive(m.get(), original.get(), 0, 25);
  AttachedData attached_before(m.get());
  mj_copyData(attached_before.get(), m.get(), original.get());
  const DataPtr attached_after(mj_makeData(m.get()));
  mj_copyData(attached_after.get(), m.get(), original.get());
  ASSERT_TRUE(Attach(m.get(), attached_after.get()));
  const std::vector<double> expected = Drive(m.get(), original.get(), 25, 25);
  EXPECT_EQ(LargestDifference(expected, Drive(m.get(), attached_before.get(), 25, 25)), 0.0);
  EXPECT_EQ(LargestDifference(expected, Drive(m.get(), attached_after.get(), 25, 25)), 0.0);
  Detach(attached_after.get());
}

INSTANTIATE_TEST_SUITE_P(
    EveryFluidBothDynamics, BranchTest,
    ::testing::Values(Case{"inertial", "rft"}, Case{"stokes", "rft"},
                      Case{"inertial", "stokeslets"}, Case{"stokes", "stokeslets"},
                      Case{"inertial", "plates"}, Case{"stokes", "plates"}),
    [](const ::testing::TestParamInfo<Case>& info) {
      return std::string(info.param.dynamics) + "_" + info.param.fluid;
    });

TEST_F(StateInDataTest, ResetDataStartsTheActuatorsFromRest) {
  const ModelPtr m = Flagellum("inertial", "rft");
  AttachedData used(m.get());
  Drive(m.get(), used.get(), 0, 50);
  mj_resetData(m.get(), used.get());
  AttachedData fresh(m.get());
  EXPECT_EQ(LargestDifference(Drive(m.get(), fresh.get(), 0, 30),
                              Drive(m.get(), used.get(), 0, 30)),
            0.0);
}

TEST_F(StateInDataTest, CopyNotAttachedIsRefusedByStep) {
  const ModelPtr m = Flagellum("inertial", "rft");
  AttachedData original(m.get());
  Drive(m.get(), original.get(), 0, 10);
  const DataPtr copy(mj_copyData(nullptr, m.get(), original.get()));
  EXPECT_FALSE(Step(m.get(), copy.get()));
  EXPECT_NE(std::string(LastError(copy.get())).find("d is not attached"), std::string::npos)
      << LastError(copy.get());
  EXPECT_EQ(copy->time, original.get()->time);  // not stepped
}

TEST_F(StateInDataTest, HugeVelocityIsRefusedInStokesDynamics) {
  const ModelPtr m = Flagellum("stokes", "rft");
  AttachedData data(m.get());
  Drive(m.get(), data.get(), 0, 5);
  data.get()->qvel[4] = 1e11;
  EXPECT_FALSE(Step(m.get(), data.get()));
  const std::string error = LastError(data.get());
  EXPECT_EQ(error.rfind(kDivergedPrefix, 0), 0u) << error;
  EXPECT_NE(error.find("the velocity of dof 4"), std::string::npos) << error;
}

TEST_F(StateInDataTest, AttachNamesTheUserdataAModelWithoutRoomNeeds) {
  const ModelPtr m = Flagellum("inertial", "rft");
  const int needed = UserdataSize(m.get());
  EXPECT_GE(m->nuserdata, needed);  // LoadModelString reserved it
  m->nuserdata = 0;
  const DataPtr d(mj_makeData(m.get()));
  ExpectInvalidArgument([&] { Attach(m.get(), d.get()); },
                        "the model has nuserdata = 0; the coupling keeps its state in the last " +
                            std::to_string(needed) + " values of mjData.userdata");
}

}  // namespace
}  // namespace ipmc::testing
