// One stepping path: the voltages a closed-loop run applied at every
// controller sample, replayed through the plain library (mj_loadXML of the
// run's model.xml, ipmc::Attach, ipmc::SetVoltages, ipmc::Step), give the
// run's states. Cases: the default job (scenarios/paper.toml), a flexible
// strip (8 rigid sub-segments per link, c1 = 150 um/mm: the stiff hinges
// need the coupling's c_eff and first-order hold), Stokes dynamics and the
// head-and-tail swimmer (models/head_and_tail.xml: a sphere head, four
// links; c1 = 150 um/mm as scenarios/head_and_tail.toml).
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "ipmc_swim/ipmc_swim.h"
#include "sim/core/scenario_overrides.h"
#include "sim/core/scenario_simulation.h"
#include "sim/io/files.h"
#include "sim/runs/closed_loop_run.h"
#include "tests/test_paths.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;

struct ReplayCase {
  const char* name;
  std::vector<std::string> settings;  // KEY=VALUE over scenarios/paper.toml
};

// One cycle at 0.5 Hz with every controller sample recorded (1 kHz).
std::vector<std::string> Short(std::vector<std::string> settings) {
  settings.insert(settings.begin(), {"cycles=1", "waveform.frequency_Hz=0.5",
                                     "output.samples_per_cycle=2000"});
  return settings;
}

ScenarioConfig CaseScenario(const ReplayCase& c) {
  std::vector<ScenarioSetting> settings;
  for (const std::string& setting : c.settings) settings.push_back(SetOption("replay", setting));
  return ScenarioWithSettings(
      "replay", (fs::path(IPMC_SWIM_SOURCE_DIR) / "scenarios" / "paper.toml").string(), settings);
}

class ReplayTest : public testing::TestWithParam<ReplayCase> {};

TEST_P(ReplayTest, LibraryStepsTheRunsModelAsTheRunDid) {
  const ScenarioConfig scenario = CaseScenario(GetParam());
  const ClosedLoopResult run = SimulateScenario(scenario);
  ASSERT_EQ(run.samples.size(), run.states.t_s.size());
  ASSERT_EQ(run.samples.size(), 2000u);  // every 1 kHz sample of the 2 s

  // The run's model.xml (WriteClosedLoopOutputs writes this text).
  std::string source;
  const fs::path path = fs::path(testing::TempDir()) / (std::string(GetParam().name) + ".xml");
  WriteFileAtomically(path.string(), ScenarioModelXml(scenario, &source));
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.string().c_str(), nullptr, error, sizeof(error));
  fs::remove(path);
  ASSERT_NE(m, nullptr) << error;
  m->nuserdata = UserdataSize(m);
  mjData* d = mj_makeData(m);
  ASSERT_TRUE(Attach(m, d));

  const int links = static_cast<int>(run.samples.front().voltage_V.size());
  const long steps_per_sample = std::lround(1e-3 / m->opt.timestep);
  double largest_rad = 0.0, worst_rad = 0.0;
  for (size_t k = 0; k < run.samples.size(); ++k) {
    ASSERT_NEAR(d->time, run.states.t_s[k], 1e-12);
    for (int i = 0; i < m->nq; ++i) {
      largest_rad = std::max(largest_rad, std::abs(run.states.qpos[k][i]));
      worst_rad = std::max(worst_rad, std::abs(d->qpos[i] - run.states.qpos[k][i]));
    }
    ASSERT_EQ(SetVoltages(d, run.samples[k].voltage_V.data(), links), links);
    for (long s = 0; s < steps_per_sample; ++s) ASSERT_TRUE(Step(m, d)) << LastError(d);
  }
  std::printf("%s: largest coordinate %.6g, largest difference %.3g (h = %g s)\n",
              GetParam().name, largest_rad, worst_rad, m->opt.timestep);
  // Measured 0 (bit for bit) in every case; the bound is the one the
  // library promises.
  EXPECT_LE(worst_rad, 1e-9 * largest_rad);
  Detach(d);
  mj_deleteData(d);
  mj_deleteModel(m);
}

INSTANTIATE_TEST_SUITE_P(
    Runs, ReplayTest,
    testing::Values(ReplayCase{"default_job", Short({})},
                    ReplayCase{"flexible", Short({"segments_per_link=8",
                                                  "waveform.c1_um_per_mm=150.0"})},
                    ReplayCase{"stokes", Short({"dynamics=\"stokes\""})},
                    ReplayCase{"head_and_tail",
                               Short({"model=\"" + std::string(IPMC_SWIM_SOURCE_DIR) +
                                          "/models/head_and_tail.xml\"",
                                      "waveform.c1_um_per_mm=150.0"})}),
    [](const testing::TestParamInfo<ReplayCase>& info) { return info.param.name; });

// A run's model.xml named as the same scenario's model is the same model:
// the scenario's settings, the damping scale among them, are not applied
// twice.
TEST(ModelXmlTest, TheSameScenarioOverARunsModelXmlIsTheSameModel) {
  const ReplayCase scaled{"scaled", Short({"hinge_damping_scale=2.5", "fluid.viscosity_Pa_s=0.002",
                                           "timestep_s=2.5e-4"})};
  const ScenarioConfig scenario = CaseScenario(scaled);
  std::string source;
  const std::string xml = ScenarioModelXml(scenario, &source);
  const fs::path path = fs::path(testing::TempDir()) / "scaled_model.xml";
  WriteFileAtomically(path.string(), xml);
  ReplayCase again = scaled;
  again.settings.push_back("model=\"" + path.string() + "\"");
  const std::string rerun_xml = ScenarioModelXml(CaseScenario(again), &source);
  fs::remove(path);
  EXPECT_EQ(rerun_xml, xml);
  EXPECT_NE(xml.find("scenario_hinge_damping_scale"), std::string::npos);
}

// A host may change m between steps, as under mj_step: the coupling takes
// its step model afresh from m before every step, so a timestep and a hinge
// damping changed after Attach step exactly as the same changes made before.
TEST(ModelChangeTest, ChangesToTheModelAfterAttachStepAsChangesBefore) {
  const std::string path = (fs::path(IPMC_SWIM_SOURCE_DIR) / "models" / "flagellum3.xml").string();
  char error[1000] = "";
  mjModel* before = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
  mjModel* after = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
  ASSERT_NE(before, nullptr) << error;
  ASSERT_NE(after, nullptr) << error;
  auto change = [](mjModel* m) {
    m->opt.timestep = 2.5e-4;
    m->dof_damping[m->jnt_dofadr[mj_name2id(m, mjOBJ_JOINT, "j2")]] *= 2.0;
  };
  before->nuserdata = after->nuserdata = UserdataSize(before);
  change(before);
  mjData* d_before = mj_makeData(before);
  mjData* d_after = mj_makeData(after);
  ASSERT_TRUE(Attach(before, d_before));
  ASSERT_TRUE(Attach(after, d_after));
  change(after);
  const double volts[3] = {2.0, -1.0, 1.5};
  for (mjData* d : {d_before, d_after}) ASSERT_EQ(SetVoltages(d, volts, 3), 3);
  for (int s = 0; s < 2000; ++s) {
    ASSERT_TRUE(Step(before, d_before)) << LastError(d_before);
    ASSERT_TRUE(Step(after, d_after)) << LastError(d_after);
  }
  EXPECT_NEAR(d_after->time, 0.5, 1e-12);  // 2000 steps of the changed 0.25 ms
  for (int i = 0; i < before->nq; ++i) EXPECT_EQ(d_after->qpos[i], d_before->qpos[i]) << i;
  EXPECT_NE(d_after->qpos[before->jnt_qposadr[1]], 0.0);  // the links moved
  for (mjData* d : {d_before, d_after}) {
    Detach(d);
    mj_deleteData(d);
  }
  mj_deleteModel(before);
  mj_deleteModel(after);
}

}  // namespace
}  // namespace ipmc
