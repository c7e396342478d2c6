// Sweeps: the table does not depend on the number of threads, shards merge
// back into the whole, overrides reach the scenario, failing points are
// recorded without stopping the others, and bad sweep files or tables give
// one-line errors. The runs are one 2 s wave period at a 0.5 ms step
// (about 0.03 s each).
#include "sim/batch/sweep.h"
#include "sim/runs/run_warnings.h"

#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/base/numbers.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/cli/sweep_command.h"
#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;
using testing::ReadFile;

const fs::path kSourceDir = IPMC_SWIM_SOURCE_DIR;

// Eight points, the keys written out of alphabetical order; the second
// key is a nested table.
constexpr char kEightPoints[] =
    "base = \"fast.toml\"\n"
    "[grid]\n"
    "\"waveform.frequency_Hz\" = [0.5, 1.0]\n"
    "actuation = [\"single\", \"distributed\"]\n"
    "controller.kp = [8.12, 4]\n";

// A fresh directory per test holding fast.toml.
class SweepTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / (std::string("ipmc_sweep_test_") + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    Write("fast.toml", testing::OneCycleScenario(0.5));
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }

  SweepPlan Parse(const std::string& text) const {
    return ParseSweep(text, (dir_ / "sweep.toml").string());
  }

  // The message of the error `text` raises, or "" (with a failure).
  std::string ErrorOf(const std::string& text) const {
    return ipmc::testing::OneLineErrorOf([&] { Parse(text); }, text);
  }

  // Runs `ipmc-swim ARGS` through the sweep commands alone.
  static int RunCommand(const std::string& args) {
    CLI::App app;
    SweepArgs sweep_args;
    AddSweepCommands(app, sweep_args);
    app.parse(args);
    return RunSweepCommandLine(app, sweep_args);
  }

  fs::path dir_;
};

TEST_F(SweepTest, GridRunsInFileOrderWithTheLastKeyFastest) {
  const SweepPlan plan = Parse(kEightPoints);
  ASSERT_EQ(plan.keys, (std::vector<std::string>{"waveform.frequency_Hz", "actuation",
                                                 "controller.kp"}));
  ASSERT_EQ(plan.points.size(), 8u);
  EXPECT_EQ(plan.links, 3);
  EXPECT_EQ(plan.points[0].values, (std::vector<std::string>{"0.5", "single", "8.12"}));
  EXPECT_EQ(plan.points[1].values, (std::vector<std::string>{"0.5", "single", "4"}));
  EXPECT_EQ(plan.points[2].values, (std::vector<std::string>{"0.5", "distributed", "8.12"}));
  EXPECT_EQ(plan.points[7].values, (std::vector<std::string>{"1", "distributed", "4"}));
  const ScenarioConfig& last = *plan.points[7].scenario;
  EXPECT_EQ(last.waveform.frequency_Hz, 1.0);
  EXPECT_EQ(last.actuation, Actuation::kDistributed);
  EXPECT_EQ(last.controller.pid.kp, 4.0);
  EXPECT_EQ(last.controller.pid.ki, 53.36);  // the rest is the base's
  EXPECT_EQ(last.run.cycles, 1);

  // A nested table and a quoted dotted key are the same key.
  const SweepPlan nested = Parse(
      "base = \"fast.toml\"\n"
      "[grid.waveform]\n"
      "frequency_Hz = [0.5, 1.0]\n");
  EXPECT_EQ(nested.keys, std::vector<std::string>{"waveform.frequency_Hz"});
  EXPECT_EQ(nested.points[1].scenario->waveform.frequency_Hz, 1.0);
}

TEST_F(SweepTest, OverridesReachEveryPartOfTheScenario) {
  const std::string paper = (kSourceDir / "scenarios" / "paper.toml").string();
  SweepPlan plan = Parse(
      "base = \"" + paper + "\"\n"
      "[set]\n"
      "cycles = 2\n"
      "[[point]]\n"
      "waveform = { kind = \"fractional\", c_um = 150.0, alpha = 0.7 }\n"
      "[[point]]\n"
      "controller = { kind = \"fractional\", gain = 10.0, order = 0.5 }\n"
      "fluid.viscosity_Pa_s = 2e-3\n"
      "[[point]]\n"
      "actuation = \"single\"\n"
      "[[point]]\n"
      "controller = { kind = \"fractional\", kp = 1.0 }\n");
  EXPECT_EQ(plan.base_path, paper);
  ASSERT_EQ(plan.points.size(), 4u);
  // Changing a table's kind drops the base's keys of the other kind
  // (paper.toml's kp, ki, kd, c0_um, ...), but not a key the point gives.
  const SweepPoint bad = plan.points.back();
  plan.points.pop_back();
  EXPECT_FALSE(bad.scenario);
  EXPECT_EQ(bad.error, (dir_ / "sweep.toml").string() +
                           ":12: controller.kp applies only to kind = \"pid\" (kind is "
                           "\"fractional\")");
  // Columns in the order the keys first appear; "" where a point keeps the base.
  EXPECT_EQ(plan.keys, (std::vector<std::string>{"waveform.kind", "waveform.c_um", "waveform.alpha",
                                                 "controller.kind", "controller.gain",
                                                 "controller.order", "fluid.viscosity_Pa_s",
                                                 "actuation", "controller.kp"}));
  EXPECT_EQ(plan.points[0].values,
            (std::vector<std::string>{"fractional", "150", "0.7", "", "", "", "", "", ""}));
  for (const SweepPoint& point : plan.points) {
    ASSERT_TRUE(point.scenario) << point.error;
    EXPECT_EQ(point.scenario->run.cycles, 2);
    EXPECT_EQ(fs::path(point.scenario->model.path),
              fs::canonical(kSourceDir / "models" / "flagellum3.xml"));
  }
  const WaveformConfig& wave = plan.points[0].scenario->waveform;
  EXPECT_EQ(wave.kind, WaveformKind::kFractional);
  EXPECT_EQ(wave.c_um, 150.0);
  EXPECT_EQ(wave.alpha, 0.7);
  EXPECT_EQ(wave.frequency_Hz, 0.01);  // paper.toml's
  const ScenarioConfig& fractional = *plan.points[1].scenario;
  EXPECT_EQ(fractional.controller.kind, ControllerKind::kFractional);
  EXPECT_EQ(fractional.controller.fractional.gain, 10.0);
  EXPECT_EQ(fractional.controller.fractional.order, 0.5);
  EXPECT_EQ(fractional.fluid.viscosity_Pa_s, 2e-3);
  EXPECT_EQ(plan.points[2].scenario->actuation, Actuation::kSingle);
}

// Sweeping the fractional integrator's realisation over
// paper_fractional.toml: "eq15" drops the base's gain, order, oustaloup_n
// and band_rad_s (eq. 15 fixes them), as a change of kind drops the keys
// of the other kind; a point that gives one of them itself is an error.
TEST_F(SweepTest, RealisationOverridesDropTheBasesOustaloupKeys) {
  const std::string base = (kSourceDir / "scenarios" / "paper_fractional.toml").string();
  SweepPlan plan = Parse("base = \"" + base + "\"\n"
                         "[grid]\n"
                         "\"controller.realisation\" = [\"oustaloup\", \"eq15\"]\n");
  ASSERT_EQ(plan.points.size(), 2u);
  for (const SweepPoint& point : plan.points) ASSERT_TRUE(point.scenario) << point.error;
  EXPECT_EQ(plan.points[0].scenario->controller.fractional.realisation,
            FractionalRealisation::kOustaloup);
  EXPECT_EQ(plan.points[1].scenario->controller.fractional.realisation,
            FractionalRealisation::kEq15);

  plan = Parse("base = \"" + base + "\"\n"
               "[[point]]\n"
               "controller = { realisation = \"eq15\", gain = 10.0 }\n");
  ASSERT_EQ(plan.points.size(), 1u);
  EXPECT_FALSE(plan.points[0].scenario);
  EXPECT_NE(plan.points[0].error.find(
                "controller.gain applies only to realisation = \"oustaloup\" (realisation is "
                "\"eq15\")"),
            std::string::npos)
      << plan.points[0].error;
}

TEST_F(SweepTest, TheWorkedExampleHasTwelvePoints) {
  const SweepPlan plan = LoadSweep((kSourceDir / "scenarios" / "sweep_frequency.toml").string());
  ASSERT_EQ(plan.points.size(), 12u);
  EXPECT_EQ(plan.keys, (std::vector<std::string>{"actuation", "waveform.frequency_Hz"}));
  EXPECT_EQ(plan.points[0].values, (std::vector<std::string>{"single", "0.005"}));
  EXPECT_EQ(plan.points[11].values, (std::vector<std::string>{"distributed", "0.04"}));
  for (const SweepPoint& point : plan.points) {
    ASSERT_TRUE(point.scenario) << point.error;
    EXPECT_EQ(point.scenario->run.cycles, 2);
  }
}

TEST_F(SweepTest, TableDoesNotDependOnJobsAndHoldsTheRunsNumbersExactly) {
  const SweepPlan plan = Parse(kEightPoints);
  SweepOptions options;
  options.jobs = 1;
  const SweepTable one = RunSweep(plan, options);
  options.jobs = 2;
  std::vector<int> reported;
  options.on_point_done = [&](const SweepProgress& p) {
    reported.push_back(p.point);
    EXPECT_EQ(p.done, static_cast<int>(reported.size()));
    EXPECT_EQ(p.total, 8);
    EXPECT_TRUE(p.ok) << p.error;
  };
  const SweepTable two = RunSweep(plan, options);
  EXPECT_EQ(reported.size(), 8u);
  EXPECT_EQ(SweepTableCsv(one), SweepTableCsv(two));
  EXPECT_EQ(SweepTableJson(one), SweepTableJson(two));

  ASSERT_EQ(one.rows.size(), 8u);
  const std::vector<std::string>& columns = one.columns;
  EXPECT_EQ(columns.size(), 1 + 3 + 2 + 3 * 5 + 12u + 7u);  // ..., the warnings and 6 checks
  auto column = [&](const std::string& name) {
    const auto it = std::find(columns.begin(), columns.end(), name);
    EXPECT_NE(it, columns.end()) << name;
    return static_cast<size_t>(it - columns.begin());
  };
  for (size_t i = 0; i < one.rows.size(); ++i) {
    EXPECT_EQ(one.rows[i][0], std::to_string(i));
    EXPECT_EQ(one.rows[i][column("status")], "ok") << one.rows[i][column("error")];
  }
  // Point 6 (1 Hz, distributed, Kp 8.12) run alone: the cells read back
  // as the very same doubles.
  const ClosedLoopResult alone = SimulateScenario(*plan.points[6].scenario);
  const std::vector<std::string>& row = one.rows[6];
  EXPECT_EQ(std::stod(row[column("link2_iae_mm_s")]), alone.links[1].iae_mm_s);
  EXPECT_EQ(std::stod(row[column("link3_clamped_fraction")]), alone.links[2].clamped_fraction);
  EXPECT_EQ(std::stod(row[column("last_cycle_com_along_mm")]), alone.swim.per_cycle.back().com_along);
  EXPECT_EQ(std::stod(row[column("mean_speed_along_mm_s")]), alone.swim.mean_speed_along_mm_s);
  EXPECT_EQ(std::stod(row[column("reynolds_swim")]), alone.swim.reynolds_swim);
  EXPECT_EQ(std::stod(row[column("link1_actuator_power_W")]), alone.energy.actuator_power_W[0]);
  EXPECT_EQ(std::stod(row[column("fluid_power_W")]), alone.energy.fluid_power_W);
  EXPECT_EQ(std::stod(row[column("cost_of_transport_J_m")]), alone.energy.cost_of_transport_J_m);
  EXPECT_GT(alone.swim.mean_speed_along_mm_s, 0.0);
  // Its warnings as the library decides them (sim/runs/run_warnings.h).
  const std::vector<std::string> warnings = RunWarningCells(ClosedLoopWarnings(alone));
  EXPECT_EQ(std::vector<std::string>(row.end() - 7, row.end()), warnings);

  const nlohmann::ordered_json json = SweepTableJson(one);
  EXPECT_EQ(json["points"][6]["point"], 6);
  EXPECT_EQ(json["points"][6]["waveform.frequency_Hz"], 1.0);
  EXPECT_EQ(json["points"][6]["actuation"], "distributed");
  EXPECT_EQ(json["points"][6]["error"], "");
  EXPECT_EQ(json["points"][6]["mean_speed_along_mm_s"].get<double>(),
            alone.swim.mean_speed_along_mm_s);
}

TEST_F(SweepTest, ShardsMergeIntoTheWholeTable) {
  const std::string sweep = Write("sweep.toml", kEightPoints);
  const std::string out = (dir_ / "out").string();
  ASSERT_EQ(RunCommand("sweep " + sweep + " --jobs 2 --out " + out + "/whole"), 0);
  ASSERT_EQ(RunCommand("sweep " + sweep + " --jobs 1 --shard 1/2 --out " + out + "/a"), 0);
  ASSERT_EQ(RunCommand("sweep " + sweep + " --jobs 2 --shard 2/2 --out " + out + "/b"), 0);
  EXPECT_EQ(LoadSweepTableCsv(out + "/a.csv").rows.size(), 4u);
  ASSERT_EQ(RunCommand("merge --out " + out + "/merged " + out + "/b.csv " + out + "/a.csv"), 0);
  EXPECT_EQ(ReadFile(out + "/merged.csv"), ReadFile(out + "/whole.csv"));
  EXPECT_EQ(ReadFile(out + "/merged.json"), ReadFile(out + "/whole.json"));
  CLI::App other;
  SweepArgs unused;
  AddSweepCommands(other, unused);
  other.add_subcommand("run");
  other.parse("run");
  EXPECT_EQ(RunSweepCommandLine(other, unused), -1);

  const SweepTable a = LoadSweepTableCsv(out + "/a.csv");
  const SweepTable b = LoadSweepTableCsv(out + "/b.csv");
  auto merge_error = [](const std::vector<SweepTable>& tables,
                        const std::vector<std::string>& sources) {
    try {
      MergeSweepTables(tables, sources);
    } catch (const std::runtime_error& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(merge_error({a}, {"a.csv"}),
            "merge: point 1 is missing (in none of a.csv; they hold points up to 6)");
  EXPECT_EQ(merge_error({a, b, a}, {"a.csv", "b.csv", "c.csv"}), "c.csv: point 0 is also in a.csv");
  SweepTable renamed = b;
  renamed.columns[2] = "actuation_mode";
  EXPECT_EQ(merge_error({a, renamed}, {"a.csv", "b.csv"}),
            "b.csv: columns differ from a.csv's (column 3: 'actuation_mode' vs 'actuation')");

  auto parse_error = [](const std::string& csv) {
    try {
      ParseSweepTableCsv(csv, "t.csv");
    } catch (const std::runtime_error& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(parse_error("x,status,error\n"),
            "t.csv:1: not a sweep table (expected columns point, ..., status, error, ...)");
  EXPECT_EQ(parse_error("point,status,error\n0,ok\n"), "t.csv:2: expected 3 cells, got 2");
  EXPECT_EQ(parse_error("point,status,error\n0,ok,\n0,ok,\n"), "t.csv:3: point 0 appears twice");
  EXPECT_EQ(parse_error("point,status,error\n-1,ok,\n"),
            "t.csv:2: point must be a whole number >= 0 (got '-1')");
  EXPECT_EQ(parse_error("point,status,error\n0,error,\"a, \"\"b\"\"\n"),
            "t.csv:2: unterminated quoted cell");
  EXPECT_EQ(ParseSweepTableCsv("point,status,error\n0,error,\"a, \"\"b\"\"\"\n", "t.csv").rows[0][2],
            "a, \"b\"");
}

// With runs_dir (sweep --keep-runs, keep_runs in the sweep file) every
// point that ran keeps its run directory, whose summary names the sweep
// and the point and holds the point's own numbers; a refused point has
// none.
TEST_F(SweepTest, KeptRunsHoldEachPointsOutputs) {
  SweepPlan plan = Parse(
      "base = \"fast.toml\"\nkeep_runs = true\n"
      "[[point]]\nactuation = \"single\"\n"
      "[[point]]\nwaveform.frequency_Hz = 0\n"
      "[[point]]\nactuation = \"distributed\"\n");
  EXPECT_TRUE(plan.keep_runs);
  EXPECT_FALSE(Parse("base = \"fast.toml\"\n[grid]\ncycles = [1]\n").keep_runs);
  SweepOptions options;
  options.jobs = 2;
  options.runs_dir = SweepRunsDir((dir_ / "table").string());
  EXPECT_EQ(options.runs_dir, (dir_ / "table_runs").string());
  const SweepTable table = RunSweep(plan, options);
  ASSERT_EQ(table.rows.size(), 3u);
  const size_t last_cycle = std::find(table.columns.begin(), table.columns.end(),
                                      "last_cycle_com_along_mm") - table.columns.begin();
  ASSERT_LT(last_cycle, table.columns.size());
  for (int index : {0, 2}) {
    const fs::path run = SweepPointRunDir(options.runs_dir, index);
    EXPECT_EQ(run, dir_ / "table_runs" / ("point_" + std::to_string(index)));
    for (const char* file : {"timeseries.csv", "states.csv", "summary.json"}) {
      EXPECT_TRUE(fs::is_regular_file(run / file)) << run / file;
    }
    const nlohmann::json summary = nlohmann::json::parse(ReadFile(run / "summary.json"));
    EXPECT_EQ(summary["inputs"]["sweep"], (dir_ / "sweep.toml").string());
    EXPECT_EQ(summary["inputs"]["sweep_point"], index);
    EXPECT_EQ(summary["actuation"], index == 0 ? "single" : "distributed");
    EXPECT_EQ(FormatShortest(summary["per_cycle"].back()["com_along_mm"].get<double>()),
              table.rows[index][last_cycle]);
  }
  EXPECT_FALSE(fs::exists(SweepPointRunDir(options.runs_dir, 1)));
}

TEST_F(SweepTest, FailingPointsAreRecordedAndTheOthersRun) {
  // No time step in this base: a point that does not set one runs at the
  // model's 1e-4 s, where 3 kHz sampling is not a whole number of steps
  // (found only when the run starts). A viscosity of 10 Pa s makes the
  // explicit drag unstable at 5e-4 s (relaxation time 6e-5 s): divergence.
  Write("no_step.toml",
        "model = \"" + (kSourceDir / "models" / "flagellum3.xml").string() +
            "\"\ncycles = 1\n[waveform]\nfrequency_Hz = 0.5\n");
  const SweepPlan plan = Parse(
      "base = \"no_step.toml\"\n"                 // 1
      "[[point]]\n"                               // 2
      "timestep_s = 5e-4\n"                       // 3
      "[[point]]\n"                               // 4
      "controller.sample_rate_Hz = 3000\n"        // 5
      "[[point]]\n"                               // 6
      "timestep_s = 5e-4\n"                       // 7
      "fluid.viscosity_Pa_s = 10\n"               // 8
      "[[point]]\n"                               // 9
      "timestep_s = 5e-4\n"                       // 10
      "waveform.frequency_Hz = 0\n"               // 11
      "[[point]]\n"                               // 12
      "timestep_s = 5e-4\n"                       // 13
      "waveform.frequency_Hz = 1.0\n");           // 14
  ASSERT_EQ(plan.points.size(), 5u);
  EXPECT_TRUE(plan.points[1].scenario);
  EXPECT_FALSE(plan.points[3].scenario);  // refused by the scenario reader, at its line
  const std::string sweep = (dir_ / "sweep.toml").string();
  EXPECT_EQ(plan.points[3].error,
            sweep + ":11: waveform: frequency_Hz must be finite and != 0 (got 0)");

  SweepOptions options;
  options.jobs = 2;
  int failures = 0;
  options.on_point_done = [&](const SweepProgress& p) { failures += p.ok ? 0 : 1; };
  const SweepTable table = RunSweep(plan, options);
  EXPECT_EQ(failures, 3);
  ASSERT_EQ(table.rows.size(), 5u);
  const size_t status = 1 + plan.keys.size();
  EXPECT_EQ(table.rows[0][status], "ok");
  EXPECT_EQ(table.rows[4][status], "ok");
  EXPECT_FALSE(table.rows[4].back().empty());
  EXPECT_EQ(table.rows[1][status], "error");
  EXPECT_NE(table.rows[1][status + 1].find("controller.sample_rate_Hz 3000 must divide the step rate"),
            std::string::npos)
      << table.rows[1][status + 1];
  EXPECT_EQ(table.rows[2][status], "error");
  EXPECT_NE(table.rows[2][status + 1].find("simulation diverged"), std::string::npos)
      << table.rows[2][status + 1];
  EXPECT_EQ(table.rows[3][status + 1], plan.points[3].error);
  EXPECT_TRUE(table.rows[2].back().empty());  // no results for a failed point
  EXPECT_EQ(SweepTableJson(table)["points"][2]["mean_speed_along_mm_s"], nullptr);
  // The CSV reads back with the quoted messages intact.
  EXPECT_EQ(ParseSweepTableCsv(SweepTableCsv(table), "t.csv").rows, table.rows);
}

TEST_F(SweepTest, BadSweepFilesGiveOneLineErrorsBeforeAnyRun) {
  Write("bad_base.toml", "model = \"nowhere.xml\"\n");
  const std::string sweep = (dir_ / "sweep.toml").string();
  const std::string fast = (dir_ / "fast.toml").string();
  const std::pair<std::string, std::string> cases[] = {
      {"base = \"fast.toml\"\n[grid]\n\"waveform.frequencyHz\" = [0.5]\n",
       ":3: unknown key 'waveform.frequencyHz' (allowed: kind, c0_um, c1_um_per_mm, "
       "c2_um_per_mm2, c_um, alpha, frequency_Hz, wavelength_mm, start_ramp_cycles)"},
      {"base = \"fast.toml\"\n[grid]\nspeed = [1]\n",
       ":3: unknown key 'speed' (allowed: include, model, link_lengths_mm, segments_per_link, plants, actuation, dynamics, hinge_damping_scale, cycles, timestep_s, strip, plant, controller, "
       "waveform, drive, fluid, metrics, electrical, output)"},
      {"base = \"fast.toml\"\n[grid]\nactuation = [\"single\"]\ncycles = [1, 1.5]\n",
       ":4: cycles must be an integer (got float)"},
      {"base = \"fast.toml\"\n[[point]]\ncycles = 1\n[[point]]\ncontroller.kp = \"8\"\n",
       ":5: controller.kp must be a number (got string)"},
      {"base = \"fast.toml\"\n[set]\nfluid = 3\n[grid]\ncycles = [1]\n",
       ":3: fluid must be a table (got integer)"},
      {"base = \"fast.toml\"\n[grid]\n\"actuation.x\" = [1]\n",
       ":3: actuation.x: actuation is not a table in " + fast + " (it is a string)"},
      {"base = \"fast.toml\"\n[grid]\ncycles = 2\n",
       ":3: grid.cycles must be an array of values (got integer)"},
      {"base = \"fast.toml\"\n[grid]\ncycles = []\n", ":3: grid.cycles must not be empty"},
      {"base = \"fast.toml\"\n[grid]\nwaveform = [{ frequency_Hz = 1.0 }]\n",
       ":3: grid.waveform must hold values, not tables (use [[point]] to change several keys "
       "together)"},
      {"base = \"fast.toml\"\n[set]\ncycles = 1\n[grid]\ncycles = [1, 2]\n",
       ":5: cycles is given twice (also on line 3)"},
      {"base = \"fast.toml\"\n[grid]\nwaveform = [1]\n\"waveform.kind\" = [\"polynomial\"]\n",
       ":4: waveform.kind and waveform (lines 3 and 4) cannot both be given"},
      {"base = \"fast.toml\"\n[grid]\n\"waveform..kind\" = [1]\n",
       ":3: 'waveform..kind' is not a dotted scenario key"},
      {"base = \"fast.toml\"\n[grid]\ncycles = [1]\n[[point]]\ncycles = 1\n",
       ":4: [grid] and [[point]] cannot be combined (use one or the other)"},
      {"base = \"fast.toml\"\n", ": needs a [grid] table or [[point]] tables"},
      {"base = \"fast.toml\"\npoint = 3\n",
       ":2: point must be one or more tables of overrides ([[point]])"},
      {"[grid]\ncycles = [1]\n", ": base is required (the scenario file to sweep)"},
      {"base = 1\n[grid]\ncycles = [1]\n", ":1: base must be a string (got integer)"},
      {"base = \"missing.toml\"\n[grid]\ncycles = [1]\n",
       ":1: base: cannot open '" + (dir_ / "missing.toml").string() + "'"},
      {"base = \"fast.toml\"\njobs = 2\n[grid]\ncycles = [1]\n",
       ":2: unknown key 'jobs' (allowed: base, gait, set, grid, point, keep_runs)"},
      {"base = \"fast.toml\"\nkeep_runs = 1\n[grid]\ncycles = [1]\n",
       ":2: keep_runs must be true or false (got integer)"},
      {"base = \"fast.toml\"\n[grid\n", ":2:6: Error while parsing table header: expected ']', "
                                        "saw '\\n'"},
  };
  for (const auto& [text, suffix] : cases) EXPECT_EQ(ErrorOf(text), sweep + suffix);
  // The base's own errors name the base.
  EXPECT_EQ(ErrorOf("base = \"bad_base.toml\"\n[grid]\ncycles = [1]\n"),
            (dir_ / "bad_base.toml").string() + ":1: model: cannot open '" +
                (dir_ / "nowhere.xml").string() + "'");

  auto shard_error = [](const std::string& text) {
    try {
      ParseSweepShard(text);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(shard_error("3/2"), "sweep: shard must be i/n with 1 <= i <= n (got '3/2')");
  EXPECT_EQ(shard_error("0/2"), "sweep: shard must be i/n with 1 <= i <= n (got '0/2')");
  EXPECT_EQ(shard_error("2"), "sweep: shard must be i/n with 1 <= i <= n (got '2')");
  EXPECT_EQ(ParseSweepShard("2/3").index, 2);
  EXPECT_EQ(ParseSweepShard("2/3").count, 3);
  SweepOptions options;
  options.jobs = 0;
  EXPECT_THROW(RunSweep(Parse(kEightPoints), options), std::invalid_argument);
}

}  // namespace
}  // namespace ipmc
