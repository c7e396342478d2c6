// The open-loop drive of `ipmc-swim run` (drive.mode, sim/core/drive_keys.h)
// on the head-and-tail swimmer (scenarios/head_and_tail_open_loop.toml):
//  - the run's swim is the swim of the same voltages, computed here from
//    their formula, applied to the run's model.xml through the plain
//    library (Attach, SetVoltages at every controller sample, Step);
//  - a closed-loop run's voltages (its timeseries.csv, every controller
//    sample) given back as drive.csv swim as the closed loop did.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "ipmc_swim/ipmc_swim.h"
#include "sim/base/numbers.h"
#include "sim/core/scenario_overrides.h"
#include "sim/core/scenario_simulation.h"
#include "sim/io/files.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/runs/output.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;

// Two cycles at 0.5 Hz with every 1 kHz controller sample recorded.
ScenarioConfig Scenario(const std::string& file, std::vector<std::string> settings) {
  settings.insert(settings.begin(), {"cycles=2", "waveform.frequency_Hz=0.5",
                                     "output.samples_per_cycle=2000"});
  std::vector<ScenarioSetting> parsed;
  for (const std::string& setting : settings) parsed.push_back(SetOption("open_loop", setting));
  return ScenarioWithSettings("open_loop",
                              (fs::path(IPMC_SWIM_SOURCE_DIR) / "scenarios" / file).string(),
                              parsed);
}

// The drive's formula, written apart from the program's: link q (0-based)
// takes A sin(2 pi f t - q phi), faded in by (1 - cos(pi t / T_r)) / 2 over
// T_r = start_ramp_cycles / f.
double SineVoltage_V(const ScenarioConfig& s, int q, double t_s) {
  const double f = s.waveform.frequency_Hz, ramp_s = s.waveform.start_ramp_cycles / f;
  const double fade = t_s < ramp_s ? 0.5 * (1.0 - std::cos(kPi * t_s / ramp_s)) : 1.0;
  return fade * s.drive.amplitude_V * std::sin(kTwoPi * f * t_s - q * s.drive.phase_lag_rad);
}

struct LibrarySwim {
  std::vector<std::vector<double>> qpos;  // at every controller sample
  std::vector<double> com_along_mm;       // per cycle, head first (-x)
};

// The scenario's model.xml stepped by the library with `volts(q, t)` set at
// every 1 ms sample.
template <typename Volts>
LibrarySwim SwimThroughTheLibrary(const ScenarioConfig& scenario, int links, const Volts& volts) {
  std::string source;
  const fs::path path = fs::path(testing::TempDir()) / "open_loop_model.xml";
  WriteFileAtomically(path.string(), ScenarioModelXml(scenario, &source));
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.string().c_str(), nullptr, error, sizeof(error));
  fs::remove(path);
  EXPECT_NE(m, nullptr) << error;
  LibrarySwim swim;
  if (m == nullptr) return swim;
  m->nuserdata = UserdataSize(m);
  mjData* d = mj_makeData(m);
  EXPECT_TRUE(Attach(m, d));
  EXPECT_EQ(LinkCount(d), links);
  const long steps_per_sample = std::lround(1e-3 / m->opt.timestep);
  const long samples_per_cycle = std::lround(1.0 / (scenario.waveform.frequency_Hz * 1e-3));
  mj_forward(m, d);
  double start_x_m = d->subtree_com[3];  // body 1, the head
  std::vector<double> v(links);
  for (int cycle = 0; cycle < scenario.run.cycles; ++cycle) {
    for (long k = 0; k < samples_per_cycle; ++k) {
      swim.qpos.emplace_back(d->qpos, d->qpos + m->nq);
      for (int q = 0; q < links; ++q) v[q] = volts(q, d->time);
      SetVoltages(d, v.data(), links);
      for (long s = 0; s < steps_per_sample; ++s) EXPECT_TRUE(Step(m, d)) << LastError(d);
    }
    // subtree_com as the last step left it (of the state at its start),
    // which is what the run's swim meter reads after a step.
    swim.com_along_mm.push_back(-(d->subtree_com[3] - start_x_m) * 1e3);
    start_x_m = d->subtree_com[3];
  }
  Detach(d);
  mj_deleteData(d);
  mj_deleteModel(m);
  return swim;
}

TEST(OpenLoopTest, SineDriveSwimsAsTheSameVoltagesThroughTheLibrary) {
  const ScenarioConfig scenario = Scenario("head_and_tail_open_loop.toml", {});
  const ClosedLoopResult run = SimulateScenario(scenario);
  ASSERT_TRUE(run.open_loop);
  EXPECT_EQ(run.controller, "sine");
  const int links = static_cast<int>(run.links.size());
  ASSERT_EQ(links, 4);
  ASSERT_EQ(run.samples.size(), 4000u);
  // The run set the formula's voltages (to rounding of the sine's argument).
  double worst_V = 0.0;
  for (const ClosedLoopSample& sample : run.samples) {
    for (int q = 0; q < links; ++q) {
      worst_V = std::max(worst_V,
                         std::abs(sample.voltage_V[q] - SineVoltage_V(scenario, q, sample.pose.t_s)));
    }
  }
  EXPECT_LE(worst_V, 1e-12);

  const LibrarySwim library = SwimThroughTheLibrary(
      scenario, links, [&](int q, double t) { return SineVoltage_V(scenario, q, t); });
  ASSERT_EQ(library.qpos.size(), run.states.qpos.size());
  double largest = 0.0, worst = 0.0;
  for (size_t k = 0; k < library.qpos.size(); ++k) {
    for (size_t i = 0; i < library.qpos[k].size(); ++i) {
      largest = std::max(largest, std::abs(run.states.qpos[k][i]));
      worst = std::max(worst, std::abs(library.qpos[k][i] - run.states.qpos[k][i]));
    }
  }
  ASSERT_EQ(library.com_along_mm.size(), 2u);
  std::printf("open-loop sine: swim per cycle %.6g, %.6g mm (library %.6g, %.6g mm); largest "
              "coordinate %.6g, largest difference %.3g\n",
              run.swim.per_cycle[0].com_along, run.swim.per_cycle[1].com_along,
              library.com_along_mm[0], library.com_along_mm[1], largest, worst);
  // Measured 0: the run's doubles, bit for bit; the bound is the library's promise.
  EXPECT_LE(worst, 1e-9 * largest);
  for (int c = 0; c < 2; ++c) {
    EXPECT_NEAR(run.swim.per_cycle[c].com_along, library.com_along_mm[c],
                1e-9 * std::abs(library.com_along_mm[c]));
  }
  // The swimmer swims, head first.
  EXPECT_GT(run.swim.per_cycle[1].com_along, 0.0);
}

TEST(OpenLoopTest, ClosedLoopVoltagesGivenAsCsvSwimAsTheClosedLoop) {
  const ScenarioConfig closed = Scenario("head_and_tail.toml", {});
  const ClosedLoopResult closed_run = SimulateScenario(closed);
  const fs::path csv = fs::path(testing::TempDir()) / "closed_loop_voltages.csv";
  WriteFileAtomically(csv.string(), ClosedLoopSamplesCsv(closed_run));
  const ScenarioConfig open =
      Scenario("head_and_tail.toml", {"drive.mode=\"csv\"", "drive.csv=\"" + csv.string() + "\""});
  const ClosedLoopResult open_run = SimulateScenario(open);
  fs::remove(csv);
  ASSERT_EQ(open_run.samples.size(), closed_run.samples.size());
  ASSERT_EQ(open_run.swim.per_cycle.size(), 2u);
  for (int c = 0; c < 2; ++c) {
    const double closed_mm = closed_run.swim.per_cycle[c].com_along;
    const double open_mm = open_run.swim.per_cycle[c].com_along;
    std::printf("cycle %d: closed loop %.9g mm, its voltages open loop %.9g mm\n", c + 1,
                closed_mm, open_mm);
    // The CSV holds the voltages to 10 significant digits (timeseries.csv):
    // measured relative difference below 1e-9.
    EXPECT_NEAR(open_mm, closed_mm, 1e-8 * std::abs(closed_mm));
  }
}

// models/head_and_tail.xml without the paper's naming: hinges h1..h4 (and
// ipmc_links naming them), no sites and no sensors.
std::string UnnamedHeadAndTail() {
  std::string xml =
      ReadTextFile(std::string(IPMC_SWIM_SOURCE_DIR) + "/models/head_and_tail.xml", "model");
  const auto erase_between = [&](const std::string& from, const std::string& to) {
    const size_t start = xml.find(from);
    ASSERT_NE(start, std::string::npos) << from;
    xml.erase(start, xml.find(to, start) + to.size() - start);
  };
  erase_between("<sensor>", "</sensor>");
  for (int q = 1; q <= 4; ++q) {
    erase_between("<site name=\"tip" + std::to_string(q) + "\"", "/>");
    // The hinge and the motor the library drives it by (ipmc_<joint>).
    const std::string j = "j" + std::to_string(q), h = "h" + std::to_string(q);
    for (const std::string& prefix : {"\"", "\"ipmc_"}) {
      for (size_t at = xml.find(prefix + j + "\""); at != std::string::npos;
           at = xml.find(prefix + j + "\"", at)) {
        xml.replace(at + prefix.size(), j.size(), h);
      }
    }
  }
  const std::string links = "data=\"j1 j2 j3 j4\"";
  const size_t at = xml.find(links);
  EXPECT_NE(at, std::string::npos);
  xml.replace(at, links.size(), "data=\"h1 h2 h3 h4\"");
  EXPECT_EQ(xml.find("\"tip1"), std::string::npos);
  EXPECT_EQ(xml.find("\"angle_"), std::string::npos);
  EXPECT_EQ(xml.find("\"j1\""), std::string::npos);
  return xml;
}

// The program takes links, tips and angles from ipmc_links and the
// geometry where a model has no hinges j1..jN, sites tipN or sensors: open
// loop it swims as the named model bit for bit (the tips are the far ends
// of the links' boxes, where the named model's sites are); closed loop its
// controllers read the hinge angles without the sensors' one-step delay.
TEST(OpenLoopTest, AModelWithoutThePapersNamesSwimsAsTheNamedOne) {
  const fs::path model = fs::path(testing::TempDir()) / "unnamed_head_and_tail.xml";
  const std::string xml = UnnamedHeadAndTail();
  WriteFileAtomically(model.string(), xml);
  const std::string unnamed = "model=\"" + model.string() + "\"";
  const ClosedLoopResult named = SimulateScenario(Scenario("head_and_tail_open_loop.toml", {}));
  const ClosedLoopResult plain =
      SimulateScenario(Scenario("head_and_tail_open_loop.toml", {unnamed}));
  const ClosedLoopResult named_closed = SimulateScenario(Scenario("head_and_tail.toml", {}));
  const ClosedLoopResult plain_closed =
      SimulateScenario(Scenario("head_and_tail.toml", {unnamed}));
  fs::remove(model);
  ASSERT_EQ(plain.states.qpos.size(), named.states.qpos.size());
  for (size_t k = 0; k < named.states.qpos.size(); ++k) {
    ASSERT_EQ(plain.states.qpos[k], named.states.qpos[k]) << k;
  }
  for (int c = 0; c < 2; ++c) {
    EXPECT_EQ(plain.swim.per_cycle[c].com_along, named.swim.per_cycle[c].com_along);
  }
  // The tips: the boxes' far ends against the sites at the same points.
  const BodyPose& a = named.samples.back().pose;
  const BodyPose& b = plain.samples.back().pose;
  ASSERT_EQ(b.tip_y_mm.size(), 4u);
  for (int q = 0; q < 4; ++q) {
    EXPECT_NEAR(b.tip_x_mm[q], a.tip_x_mm[q], 1e-12);
    EXPECT_NEAR(b.tip_y_mm[q], a.tip_y_mm[q], 1e-12);
  }
  EXPECT_NEAR(plain.swim.reynolds_tip, named.swim.reynolds_tip, 1e-12 * named.swim.reynolds_tip);
  const double named_mm = named_closed.swim.per_cycle[1].com_along;
  const double plain_mm = plain_closed.swim.per_cycle[1].com_along;
  std::printf("closed loop, cycle 2: named %.9g mm, without names (no sensor delay) %.9g mm "
              "(%.3g)\n",
              named_mm, plain_mm, plain_mm / named_mm - 1.0);
  // Measured 8.77e-5 of the swim (the sensors' one step of 0.5 ms).
  EXPECT_NEAR(plain_mm, named_mm, 1e-3 * std::abs(named_mm));
}

}  // namespace
}  // namespace ipmc
