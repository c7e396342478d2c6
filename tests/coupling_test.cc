// State semantics of the coupling (ipmc_swim.h): a restored copy steps bit
// for bit like the original, rewinds are reset explicitly or reported
// through MuJoCo's warnings, and an mjData copy has no coupling until
// attached.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <string>
#include <vector>

#include "ipmc_swim/ipmc_swim.h"
#include "sim/base/numbers.h"
#include "tests/test_util.h"

namespace ipmc::testing {
namespace {

class CouplingStateTest : public MujocoWarnings {};

constexpr int kLinks = 3;
constexpr int kStepsPerVoltage = 10;  // 1 ms at the model's 0.1 ms step

// The paper's free flagellum: drag, head and three IPMC links, each three
// sub-segments (so that each step's curvature is found by Newton from the
// last one, which is part of the state).
ModelPtr FreeFlagellum() {
  FlagellumSpec spec;
  spec.segments_per_link = 3;
  return LoadModelString(GenerateFlagellumMjcf(spec));
}

// An mjData attached for its lifetime.
struct AttachedData {
  explicit AttachedData(const mjModel* m) : d(mj_makeData(m)) { EXPECT_TRUE(Attach(m, d.get())); }
  ~AttachedData() { Detach(d.get()); }
  mjData* get() const { return d.get(); }
  DataPtr d;
};

// Distinct sines on the three links, changed every 1 ms.
std::vector<double> VoltagesAt(long step, double dt_s) {
  const double t_s = step * dt_s;
  return {3.0 * std::sin(kTwoPi * 5.0 * t_s), -2.0 * std::cos(kTwoPi * 7.0 * t_s),
          1.5 * std::sin(kTwoPi * 11.0 * t_s + 0.3)};
}

// Steps [first, first + count) of the voltage programme, recording after
// each step qpos, qvel, the motors' ctrl (the active moments the coupling
// writes), actuator_force and the links' free deflections.
std::vector<double> Drive(const mjModel* m, mjData* d, long first, long count) {
  std::vector<double> trace;
  for (long step = first; step < first + count; ++step) {
    if (step % kStepsPerVoltage == 0) {
      const std::vector<double> volts = VoltagesAt(step, m->opt.timestep);
      SetVoltages(d, volts.data(), kLinks);
    }
    mj_step(m, d);
    trace.insert(trace.end(), d->qpos, d->qpos + m->nq);
    trace.insert(trace.end(), d->qvel, d->qvel + m->nv);
    trace.insert(trace.end(), d->ctrl, d->ctrl + m->nu);
    trace.insert(trace.end(), d->actuator_force, d->actuator_force + m->nu);
    for (int q = 0; q < kLinks; ++q) trace.push_back(LinkFreeDeflection_mm(d, q));
  }
  return trace;
}

// EXPECT_EQ on every value, stopping at the first difference.
void ExpectBitIdentical(const std::vector<double>& expected, const std::vector<double>& actual) {
  ASSERT_EQ(expected.size(), actual.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(expected[i], actual[i]) << std::setprecision(17) << expected[i] << " vs "
                                      << actual[i] << ": value " << i << " of " << expected.size();
    if (expected[i] != actual[i]) return;
  }
}

constexpr long kBefore = 2000;  // 0.2 s before the snapshot
constexpr long kAfter = 1500;   // 0.15 s after it, 150 voltage changes

TEST_F(CouplingStateTest, RestoredCopyStepsBitIdentically) {
  const ModelPtr m = FreeFlagellum();
  AttachedData original(m.get());
  Drive(m.get(), original.get(), 0, kBefore);
  const DataPtr saved(mj_makeData(m.get()));
  mj_copyData(saved.get(), m.get(), original.get());
  const CouplingState state = SaveState(original.get());
  ASSERT_EQ(state.voltage_V.size(), static_cast<size_t>(kLinks));
  ASSERT_FALSE(state.actuator_state.empty());
  const std::vector<double> continued = Drive(m.get(), original.get(), kBefore, kAfter);

  AttachedData restored(m.get());
  mj_copyData(restored.get(), m.get(), saved.get());
  RestoreState(restored.get(), state);
  ExpectBitIdentical(continued, Drive(m.get(), restored.get(), kBefore, kAfter));

  // The state is in mjData.userdata: the copy alone continues too.
  AttachedData unrestored(m.get());
  mj_copyData(unrestored.get(), m.get(), saved.get());
  ExpectBitIdentical(continued, Drive(m.get(), unrestored.get(), kBefore, kAfter));
}

TEST_F(CouplingStateTest, RestoringIntoTheSameDataRewindsIt) {
  const ModelPtr m = FreeFlagellum();
  AttachedData data(m.get());
  Drive(m.get(), data.get(), 0, kBefore);
  const DataPtr saved(mj_makeData(m.get()));
  mj_copyData(saved.get(), m.get(), data.get());
  const CouplingState state = SaveState(data.get());
  const std::vector<double> first = Drive(m.get(), data.get(), kBefore, kAfter);
  mj_copyData(data.get(), m.get(), saved.get());
  RestoreState(data.get(), state);  // a declared rewind: no warning
  ExpectBitIdentical(first, Drive(m.get(), data.get(), kBefore, kAfter));
}

TEST_F(CouplingStateTest, SavingChangesTheOriginalOnlyWithinTheTolerance) {
  const ModelPtr m = FreeFlagellum();
  AttachedData saved_once(m.get()), never_saved(m.get());
  Drive(m.get(), saved_once.get(), 0, kBefore);
  Drive(m.get(), never_saved.get(), 0, kBefore);
  SaveState(saved_once.get());  // restarts the link models' integration here
  Drive(m.get(), saved_once.get(), kBefore, kAfter);
  Drive(m.get(), never_saved.get(), kBefore, kAfter);
  double largest_relative = 0;
  for (int q = 0; q < kLinks; ++q) {
    const double a = LinkFreeDeflection_mm(saved_once.get(), q);
    const double b = LinkFreeDeflection_mm(never_saved.get(), q);
    largest_relative = std::max(largest_relative, std::abs(a - b) / std::abs(b));
  }
  std::printf("free deflections 0.15 s after a save: largest relative change %.3g\n",
              largest_relative);
  // The save restarts the link models' integration once more; the two
  // banks then restart together at the next 0.1 s window
  // (ipmc_actuator_bank.h, "Stepping"), and the effect stays below the
  // CVODE tolerance, 1e-6 relative. Measured 3.5e-7.
  EXPECT_LT(largest_relative, 1e-6);
}

TEST_F(CouplingStateTest, ResetStateAfterResetDataStartsFromRest) {
  const ModelPtr m = FreeFlagellum();
  AttachedData fresh(m.get());
  const std::vector<double> from_rest = Drive(m.get(), fresh.get(), 0, kAfter);

  AttachedData reused(m.get());
  Drive(m.get(), reused.get(), 0, kBefore);
  mj_resetData(m.get(), reused.get());
  ResetState(reused.get());  // declared: no warning
  const CouplingState state = SaveState(reused.get());
  EXPECT_EQ(state.time_s, 0.0);
  EXPECT_EQ(state.voltage_V, std::vector<double>(kLinks, 0.0));
  EXPECT_EQ(state.clamp_count, 0);
  for (double x : state.actuator_state) EXPECT_EQ(x, 0.0);
  ExpectBitIdentical(from_rest, Drive(m.get(), reused.get(), 0, kAfter));
}

// mj_resetData zeroes userdata, where the state lives: the actuators start
// from rest, as declared. Only a d->time set back by hand, the state left
// as it was, is an undeclared rewind.
TEST_F(CouplingStateTest, ResetDataStartsFromRestAndAnUndeclaredRewindWarns) {
  ExpectWarning("d->time went back from 0.1999 s to 0 s", 1);
  const ModelPtr m = FreeFlagellum();
  AttachedData fresh(m.get());
  const std::vector<double> from_rest = Drive(m.get(), fresh.get(), 0, kAfter);

  AttachedData reused(m.get());
  Drive(m.get(), reused.get(), 0, kBefore);
  mj_resetData(m.get(), reused.get());
  ExpectBitIdentical(from_rest, Drive(m.get(), reused.get(), 0, kAfter));
  EXPECT_EQ(Count("went back"), 0);

  AttachedData rewound(m.get());
  Drive(m.get(), rewound.get(), 0, kBefore);
  mj_resetData(m.get(), rewound.get());
  Drive(m.get(), rewound.get(), 0, kBefore);
  rewound.get()->time = 0;
  rewound.get()->qpos[0] = 0;
  Drive(m.get(), rewound.get(), 0, 1);
  EXPECT_EQ(Count("went back"), 1);
  for (const std::string& warning : Received()) std::printf("warning: %s\n", warning.c_str());
}

TEST_F(CouplingStateTest, CopiedDataHasNoCouplingUntilAttached) {
  const ModelPtr m = FreeFlagellum();
  AttachedData data(m.get());
  Drive(m.get(), data.get(), 0, 100);
  const DataPtr copy(mj_makeData(m.get()));
  mj_copyData(copy.get(), m.get(), data.get());
  EXPECT_FALSE(IsAttached(copy.get()));
  ExpectInvalidArgument([&] { SaveState(copy.get()); }, "not attached");
  ExpectInvalidArgument([&] { RestoreState(copy.get(), SaveState(data.get())); }, "not attached");
  ExpectInvalidArgument([&] { ResetState(copy.get()); }, "not attached");
}

TEST_F(CouplingStateTest, RestoreRejectsAMalformedStateNamingTheFieldAndLeavesTheStateAlone) {
  const ModelPtr m = FreeFlagellum();
  AttachedData data(m.get());
  Drive(m.get(), data.get(), 0, 200);
  const CouplingState good = SaveState(data.get());
  const auto expect_rejected = [&](auto change, const std::string& field) {
    CouplingState bad = good;
    change(bad);
    ExpectInvalidArgument([&] { RestoreState(data.get(), bad); }, field);
    const CouplingState after = SaveState(data.get());
    EXPECT_EQ(after.time_s, good.time_s) << field;
    EXPECT_EQ(after.actuator_state, good.actuator_state) << field;
    EXPECT_EQ(after.voltage_V, good.voltage_V) << field;
    EXPECT_EQ(after.curvature_1_m, good.curvature_1_m) << field;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expect_rejected([](CouplingState& s) { s.actuator_state.pop_back(); },
                  "actuator_state must hold");
  expect_rejected([](CouplingState& s) { s.voltage_V.push_back(1.0); }, "voltage_V must hold 3");
  expect_rejected([](CouplingState& s) { s.curvature_1_m.clear(); },
                  "curvature_1_m must hold 3");
  expect_rejected([&](CouplingState& s) { s.actuator_state[4] = nan; },
                  "actuator_state[4] must be finite");
  expect_rejected([&](CouplingState& s) { s.voltage_V[1] = nan; }, "voltage_V[1] must be finite");
  expect_rejected([](CouplingState& s) { s.clamp_count = -1; }, "clamp_count must be >= 0");
  expect_rejected([](CouplingState& s) { s.voltage_V[2] = 150.0; },
                  "voltage_V[2] = 150 V is outside the model's range [-100, 100] V");
  expect_rejected([&](CouplingState& s) { s.time_s = data.get()->time + 1e-3; },
                  "time_s must be finite and <= d->time");
}

}  // namespace
}  // namespace ipmc::testing
