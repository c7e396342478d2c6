// Runs that would take no step (or more than can finish) are refused with
// one line instead of "succeeding" with all-zero metrics.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/core/step_count.h"
#include "tests/cli_util.h"

namespace ipmc::testing {
namespace {

namespace fs = std::filesystem;

TEST(StepCountTest, RoundsTheIntervalToWholeSteps) {
  EXPECT_EQ(CheckedStepCount(100.0, 5e-4, 1, "cycle"), 200000);  // the paper's 0.01 Hz at 0.5 ms
  EXPECT_EQ(CheckedStepCount(1e-3, 5e-4, 2, "sample"), 2);
}

void ExpectRefused(double interval_s, double timestep_s, long min_steps, const std::string& fragment) {
  try {
    CheckedStepCount(interval_s, timestep_s, min_steps, "scenario.toml: one wave cycle");
    FAIL() << "accepted " << interval_s << " s at " << timestep_s << " s";
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("scenario.toml: one wave cycle"), std::string::npos) << message;
    EXPECT_NE(message.find(fragment), std::string::npos) << message;
  }
}

TEST(StepCountTest, RefusesZeroStepsHugeCountsAndBadTimeSteps) {
  ExpectRefused(1e-300, 5e-4, 1, "allowed [1, 1e+15]");
  ExpectRefused(1e300, 5e-4, 1, "allowed [1, 1e+15]");
  ExpectRefused(1e-3, 5e-4, 3, "allowed [3, 1e+15]");  // fewer steps than one controller sample
  ExpectRefused(1.0, 0.0, 1, "time step must be finite and > 0");
  ExpectRefused(1.0, std::nan(""), 1, "time step must be finite and > 0");
  ExpectRefused(std::nan(""), 5e-4, 1, "finite time > 0");
}

// The paper scenario with its model path made absolute and one line replaced.
fs::path ScenarioWith(const fs::path& dir, const std::string& key_line, const std::string& replacement) {
  std::ifstream in(fs::path(IPMC_SWIM_SOURCE_DIR) / "scenarios" / "paper.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string scenario = text.str();
  scenario = std::regex_replace(scenario, std::regex("model = \"\\.\\./models/"),
                                "model = \"" + std::string(IPMC_SWIM_SOURCE_DIR) + "/models/");
  const size_t at = scenario.find(key_line);
  EXPECT_NE(at, std::string::npos) << key_line;
  scenario.replace(at, key_line.size(), replacement);
  const fs::path path = dir / "scenario.toml";
  std::ofstream(path) << scenario;
  return path;
}

TEST(StepCountTest, CommandsRefuseRunsWithoutStepsAndLeaveNoOutput) {
  const fs::path dir = FreshDir("step_count");
  // Too slow a wave has too many steps a cycle; too fast a one too few
  // controller samples (closed_loop_run.h, RequireSamplesPerWaveCycle).
  const std::pair<std::string, std::string> refusals[] = {
      {"1e-300", "one wave cycle (waveform.frequency_Hz)"},
      {"1e300", "a cycle takes at least 10 controller samples: at most 100 Hz"}};
  for (const auto& [frequency, message] : refusals) {
    const fs::path scenario = ScenarioWith(dir, "frequency_Hz = 0.01", "frequency_Hz = " + frequency);
    const CommandResult run = RunCli("run " + scenario.string() + " --out " + (dir / "out").string());
    EXPECT_EQ(run.exit_code, 1) << run.output;
    EXPECT_NE(run.output.find(message), std::string::npos) << run.output;
    EXPECT_EQ(CountLines(run.output), 1) << run.output;
    EXPECT_FALSE(fs::exists(dir / "out" / "summary.json"));
  }
  const CommandResult bench = RunCli("bench --duration-s 1e300 --out " + (dir / "b.csv").string());
  EXPECT_NE(bench.exit_code, 0) << bench.output;
  EXPECT_NE(bench.output.find("bench: the experiment (--duration-s)"), std::string::npos) << bench.output;
  EXPECT_FALSE(fs::exists(dir / "b.csv"));
  fs::remove_all(dir);
}

// The run size limits of sim/core/step_count.h: refused with the estimate
// beyond 1e8 steps or 2 GB of samples unless allowed; never beyond 1e15.
TEST(StepCountTest, RunSizeIsRefusedWithItsEstimateUnlessAllowed) {
  EXPECT_NO_THROW(CheckRunSize(1e8, 2e9, false, "run"));
  EXPECT_NO_THROW(CheckRunSize(1e12, 1e12, true, "run"));
  for (const auto& [steps, bytes] : {std::pair{1.01e8, 1.0}, std::pair{1.0, 2.01e9}}) {
    try {
      CheckRunSize(steps, bytes, false, "x.toml: the run");
      ADD_FAILURE() << steps << " steps, " << bytes << " bytes accepted";
    } catch (const std::invalid_argument& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind("x.toml: the run needs ", 0), 0u) << message;
      EXPECT_NE(message.find("--allow-long"), std::string::npos) << message;
    }
  }
  // 1e9 steps at 6 us: 6000 s = 100 min.
  try {
    CheckRunSize(1e9, 1e3, false, "run");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("about 100 min"), std::string::npos) << e.what();
  }
  EXPECT_THROW(CheckRunSize(2e15, 1.0, true, "run"), std::invalid_argument);
  EXPECT_THROW(CheckRunSize(std::nan(""), 1.0, true, "run"), std::invalid_argument);
}

}  // namespace
}  // namespace ipmc::testing
