// The library's edges (ipmc_swim.h): what MuJoCo would take silently, the
// coupling refuses in one line. Absurd parameters at Attach, a non-finite
// d->time at Step and SetVoltages, a voltage beyond the limit at
// RestoreState; a step that diverges (MuJoCo's bad-state checks reset the
// data, or the state is not finite after it) makes Step return false with
// LastError naming the time and the degree of freedom, in both dynamics.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "ipmc_swim/ipmc_swim.h"
#include "sim/base/numbers.h"
#include "tests/test_util.h"

namespace ipmc::testing {
namespace {

class LibraryRefusalsTest : public MujocoWarnings {};

// The paper's free flagellum (three rigid links) with `custom` added to
// its <custom> fields.
std::string FlagellumXml(const std::string& custom = "") {
  std::string xml = GenerateFlagellumMjcf(FlagellumSpec{});
  const size_t end = xml.find("  </custom>");
  EXPECT_NE(end, std::string::npos);
  return xml.insert(end, custom);
}

// An mjData attached for its lifetime.
struct AttachedData {
  explicit AttachedData(const mjModel* m) : d(mj_makeData(m)) { EXPECT_TRUE(Attach(m, d.get())); }
  ~AttachedData() { Detach(d.get()); }
  mjData* get() const { return d.get(); }
  DataPtr d;
};

// The one-line message of the std::invalid_argument Attach throws for the
// model `xml`.
std::string AttachError(const std::string& xml) {
  const ModelPtr m = LoadModelString(xml);
  const DataPtr d(mj_makeData(m.get()));
  try {
    Attach(m.get(), d.get());
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    return message;
  }
  ADD_FAILURE() << "Attach accepted:\n" << xml;
  return "";
}

TEST_F(LibraryRefusalsTest, AttachRefusesAnAbsurdStaticGainNamingTheRange) {
  const std::string error =
      AttachError(FlagellumXml("    <numeric name=\"ipmc_a0_mm_per_V\" data=\"1e300 1 1\"/>\n"));
  EXPECT_NE(error.find("link 1"), std::string::npos) << error;
  EXPECT_NE(error.find("a0_mm_per_V must be nonzero and in [-1000, 1000] mm/V"),
            std::string::npos)
      << error;
}

TEST_F(LibraryRefusalsTest, AttachRefusesAStokesletBlobLongerThanTheBody) {
  const std::string error = AttachError(
      FlagellumXml("    <text name=\"ipmc_fluid_model\" data=\"stokeslets\"/>\n"
                   "    <numeric name=\"ipmc_fluid_stokeslet_blob_m\" data=\"1e300\"/>\n"));
  EXPECT_NE(error.find("ipmc_fluid_stokeslet_blob_m"), std::string::npos) << error;
  EXPECT_NE(error.find("must be at most the body's length"), std::string::npos) << error;
}

TEST_F(LibraryRefusalsTest, NonFiniteTimeIsRefusedByStepAndSetVoltages) {
  const ModelPtr m = LoadModelString(FlagellumXml());
  AttachedData data(m.get());
  data.get()->time = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(Step(m.get(), data.get()));
  EXPECT_STREQ(LastError(data.get()), "d->time is NaN (it must be finite)");
  const double volts[3] = {1.0, 1.0, 1.0};
  ExpectInvalidArgument([&] { SetVoltages(data.get(), volts, 3); },
                        "d->time is NaN (it must be finite)");
}

TEST_F(LibraryRefusalsTest, RestoreStateRefusesAVoltageBeyondTheLimitOfSetVoltages) {
  const ModelPtr m = LoadModelString(FlagellumXml());
  AttachedData data(m.get());
  CouplingState state = SaveState(data.get());
  for (double volts : {150.0, 1e6}) {
    state.voltage_V[2] = volts;
    ExpectInvalidArgument([&] { RestoreState(data.get(), state); },
                          "voltage_V[2] = " + FormatShortest(volts) +
                              " V is outside the model's range [-100, 100] V");
  }
}

// mj_step's mj_checkVel finds the velocity beyond mjMAXVAL (1e10) and
// resets the data; the step reports it rather than returning from a
// reset state.
TEST_F(LibraryRefusalsTest, HugeVelocityFailsTheInertialStepNamingTheDof) {
  ExpectWarning("Nan, Inf or huge value in QVEL");
  const ModelPtr m = LoadModelString(FlagellumXml());
  AttachedData data(m.get());
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(Step(m.get(), data.get())) << LastError(data.get());
  const double start_s = data.get()->time;
  data.get()->qvel[3] = 1e11;
  EXPECT_FALSE(Step(m.get(), data.get()));
  const std::string error = LastError(data.get());
  char head[80];
  std::snprintf(head, sizeof(head), "%s%.9g s: ", kDivergedPrefix, start_s);
  EXPECT_EQ(error.rfind(head, 0), 0u) << error;
  EXPECT_NE(error.find("bad velocity (qvel) at dof 3 (joint 'j1') and reset the data"),
            std::string::npos)
      << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}

TEST_F(LibraryRefusalsTest, HugePositionFailsTheStokesStepNamingTheJoint) {
  const ModelPtr m = LoadModelString(
      FlagellumXml("    <text name=\"ipmc_dynamics\" data=\"stokes\"/>\n"));
  AttachedData data(m.get());
  ASSERT_TRUE(Step(m.get(), data.get())) << LastError(data.get());
  data.get()->qpos[4] = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(Step(m.get(), data.get()));
  const std::string error = LastError(data.get());
  EXPECT_EQ(error.rfind(kDivergedPrefix, 0), 0u) << error;
  EXPECT_NE(error.find("the position qpos[4] (joint 'j2') is not finite"), std::string::npos)
      << error;
}

// A time step far beyond the hinges' relaxation time makes an explicit
// step (RK4: the coupling's c_eff, which keeps Euler and implicit steps
// stable at any step, is for those two only) grow without bound: Step
// fails once, with the time of the step that diverged, rather than
// stepping on from MuJoCo's reset.
TEST_F(LibraryRefusalsTest, DivergingInertialRunFailsItsStep) {
  FlagellumSpec spec;
  spec.integrator = "RK4";
  spec.timestep_s = 5e-2;
  spec.segments_per_link = 8;
  const ModelPtr m = LoadModelString(GenerateFlagellumMjcf(spec));
  AttachedData data(m.get());
  const double volts[3] = {2.0, -2.0, 2.0};
  SetVoltages(data.get(), volts, 3);
  int step = 0;
  while (step < 10000 && Step(m.get(), data.get())) ++step;
  ASSERT_LT(step, 10000) << "the run did not diverge";
  const std::string error = LastError(data.get());
  EXPECT_EQ(error.rfind(kDivergedPrefix, 0), 0u) << error;
  EXPECT_NE(error.find("dof"), std::string::npos) << error;
}

// The generated flexible model (8 sub-segments per link) that diverged at
// 3.7 ms when stepped without the program's c_eff steps a second through
// the library as it is: Attach gives its stiff hinges c_eff.
TEST_F(LibraryRefusalsTest, GeneratedFlexibleModelStepsStably) {
  FlagellumSpec spec;
  spec.segments_per_link = 8;
  const ModelPtr m = LoadModelString(GenerateFlagellumMjcf(spec));
  AttachedData data(m.get());
  const double volts[3] = {2.0, -2.0, 2.0};
  SetVoltages(data.get(), volts, 3);
  while (data.get()->time < 1.0) ASSERT_TRUE(Step(m.get(), data.get())) << LastError(data.get());
  for (int i = 0; i < m->nq; ++i) EXPECT_LT(std::abs(data.get()->qpos[i]), 1.0);  // bent, not blown up
}

}  // namespace
}  // namespace ipmc::testing
