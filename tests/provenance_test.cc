// A run's summary.json records what made it (program version, the resolved
// scenario, the model's SHA-256), and `ipmc-swim run SUMMARY.json` makes it
// again bit for bit; `run --set KEY=VALUE` and `--cycles N` change a
// scenario's keys as a sweep's [set] does, and name the option and the key
// when they are wrong.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "ipmc_swim/ipmc_swim.h"
#include "sim/core/data_paths.h"
#include "sim/core/sha256.h"

namespace ipmc {
namespace {

// A run's printed output without its last line, "wrote DIR/...", which
// names the run's own folder.
std::string WithoutWrittenLine(const std::string& output) {
  const std::size_t wrote = output.rfind("wrote ");
  return wrote == std::string::npos ? output : output.substr(0, wrote);
}

namespace fs = std::filesystem;
using testing::CommandResult;
using testing::FreshDir;
using testing::RunCli;
using testing::ReadFile;

std::string Quoted(const fs::path& path) { return "'" + path.string() + "'"; }

// One cycle of 2 s at a 0.5 ms step with 20 samples, on `model`.
fs::path ShortScenario(const fs::path& dir, const fs::path& model) {
  const fs::path path = dir / "short.toml";
  std::ofstream(path) << "model = \"" << model.string() << "\"\n"
                      << "cycles = 1\ntimestep_s = 5e-4\n"
                      << "[waveform]\nfrequency_Hz = 0.5\n[output]\nsamples_per_cycle = 20\n";
  return path;
}

nlohmann::json Summary(const fs::path& dir) {
  return nlohmann::json::parse(ReadFile(dir / "summary.json"));
}

class ProvenanceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = FreshDir(std::string("provenance_") +
                    ::testing::UnitTest::GetInstance()->current_test_info()->name());
    model_ = dir_ / "model.xml";
    fs::copy_file(ModelsDir() + "/flagellum3.xml", model_);
    scenario_ = ShortScenario(dir_, model_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_, model_, scenario_;
};

TEST_F(ProvenanceTest, ARunMadeAgainFromItsSummaryIsTheSameBitForBit) {
  const CommandResult first = RunCli("run " + Quoted(scenario_) + " --out " + Quoted(dir_ / "a"));
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const nlohmann::json a = Summary(dir_ / "a");
  const nlohmann::json& inputs = a["inputs"];
  EXPECT_EQ(inputs["program_version"], ProgramVersion());
  EXPECT_EQ(inputs["model_sha256"], Sha256Hex(ReadFile(model_)));
  const std::string resolved = inputs["resolved_scenario"].get<std::string>();
  EXPECT_NE(resolved.find(model_.string()), std::string::npos) << resolved;
  EXPECT_NE(resolved.find("kp = 8.12"), std::string::npos) << "defaults are filled in";

  const CommandResult again = RunCli("run " + Quoted(dir_ / "a" / "summary.json") + " --out " +
                                     Quoted(dir_ / "b"));
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(WithoutWrittenLine(again.output), WithoutWrittenLine(first.output));
  EXPECT_EQ(ReadFile(dir_ / "b" / "timeseries.csv"), ReadFile(dir_ / "a" / "timeseries.csv"));
  EXPECT_EQ(ReadFile(dir_ / "b" / "states.csv"), ReadFile(dir_ / "a" / "states.csv"));
  nlohmann::json b = Summary(dir_ / "b");
  EXPECT_EQ(b["inputs"]["resolved_scenario"], inputs["resolved_scenario"]);
  EXPECT_EQ(b["inputs"]["model_sha256"], inputs["model_sha256"]);
  nlohmann::json a_results = a;
  a_results.erase("inputs");
  b.erase("inputs");
  EXPECT_EQ(b, a_results);
}

TEST_F(ProvenanceTest, AChangedModelIsRefused) {
  ASSERT_EQ(RunCli("run " + Quoted(scenario_) + " --out " + Quoted(dir_ / "a")).exit_code, 0);
  std::ofstream(model_, std::ios::app) << "<!-- edited -->\n";
  const CommandResult again = RunCli("run " + Quoted(dir_ / "a" / "summary.json") + " --out " +
                                     Quoted(dir_ / "b"));
  EXPECT_EQ(again.exit_code, 1) << again.output;
  EXPECT_NE(again.output.find("summary.json: the model '" + model_.string() +
                              "' has changed since the run"),
            std::string::npos)
      << again.output;
  EXPECT_EQ(testing::CountLines(again.output), 1) << again.output;
  EXPECT_FALSE(fs::exists(dir_ / "b"));
}

TEST_F(ProvenanceTest, SetAndCyclesActLikeTheKeysInTheFile) {
  // The same scenario with controller.kp = 4 and 2 cycles in the file.
  std::ofstream(dir_ / "edited.toml") << ReadFile(scenario_) << "[controller]\nkp = 4.0\n";
  std::string edited = ReadFile(dir_ / "edited.toml");
  edited.replace(edited.find("cycles = 1"), 10, "cycles = 2");
  std::ofstream(dir_ / "edited.toml") << edited;
  const CommandResult file = RunCli("run " + Quoted(dir_ / "edited.toml") + " --out " +
                                    Quoted(dir_ / "file"));
  ASSERT_EQ(file.exit_code, 0) << file.output;
  const CommandResult set = RunCli("run " + Quoted(scenario_) + " --set controller.kp=4.0" +
                                   " --cycles 2 --out " + Quoted(dir_ / "set"));
  ASSERT_EQ(set.exit_code, 0) << set.output;
  EXPECT_EQ(WithoutWrittenLine(set.output), WithoutWrittenLine(file.output));
  EXPECT_EQ(ReadFile(dir_ / "set" / "timeseries.csv"), ReadFile(dir_ / "file" / "timeseries.csv"));
  const nlohmann::json inputs = Summary(dir_ / "set")["inputs"];
  EXPECT_EQ(inputs["resolved_scenario"], Summary(dir_ / "file")["inputs"]["resolved_scenario"]);
  EXPECT_EQ(inputs["set"], nlohmann::json::array({"controller.kp=4.0"}));
  EXPECT_EQ(inputs["cycles"], 2);
}

TEST_F(ProvenanceTest, BadOverridesNameTheOptionAndTheKey) {
  const std::string run = "run " + Quoted(scenario_) + " --out " + Quoted(dir_ / "out");
  const struct {
    std::string options, message;
  } cases[] = {
      {"--set controller.kp=-1", "run: --set controller.kp=-1: controller.kp must be >= 0 (got -1)"},
      {"--set waveform.kp=1", "run: --set waveform.kp=1: unknown key 'waveform.kp' (allowed: kind, "},
      {"--set actuation=single", "run: --set actuation=single: "},
      {"--set cycles", "run: --set must be KEY=VALUE (one line), got 'cycles'"},
      {"--cycles 0", "run: --cycles 0: cycles must be >= 1 (got 0)"},
      {"--set cycles=2 --cycles 3", "run: --cycles 3: "},
      {"--set controller.kind='\"lqr\"'",
       "controller.kind must be \"pid\" or \"fractional\" (got \"lqr\")"},
  };
  for (const auto& c : cases) {
    const CommandResult result = RunCli(run + " " + c.options);
    EXPECT_EQ(result.exit_code, 1) << c.options << ": " << result.output;
    EXPECT_NE(result.output.find(c.message), std::string::npos) << c.options << ": " << result.output;
    EXPECT_EQ(testing::CountLines(result.output), 1) << result.output;
    EXPECT_FALSE(fs::exists(dir_ / "out")) << c.options;
  }
  const CommandResult bare = RunCli(run + " --set actuation=single");
  EXPECT_NE(bare.output.find("(VALUE is TOML: quote strings, --set 'actuation=\"single\"')"),
            std::string::npos)
      << bare.output;
  const CommandResult summary =
      RunCli("run " + Quoted(dir_ / "summary.json") + " --cycles 2");
  EXPECT_EQ(summary.exit_code, 1);
  EXPECT_NE(summary.output.find("run: --set and --cycles apply to scenario files"),
            std::string::npos)
      << summary.output;
}

TEST_F(ProvenanceTest, ASweepTableKeepsEachPointsResolvedScenario) {
  std::ofstream(dir_ / "sweep.toml") << "base = \"short.toml\"\n"
                                     << "[grid]\n\"controller.kp\" = [4.0, 8.5]\n";
  const CommandResult sweep = RunCli("sweep " + Quoted(dir_ / "sweep.toml") + " --jobs 2 --out " +
                                     Quoted(dir_ / "table"));
  ASSERT_EQ(sweep.exit_code, 0) << sweep.output;
  const nlohmann::json table = nlohmann::json::parse(ReadFile(dir_ / "table.json"));
  EXPECT_EQ(table["program_version"], ProgramVersion());
  ASSERT_EQ(table["provenance"].size(), 2u);
  for (int point = 0; point < 2; ++point) {
    const nlohmann::json& entry = table["provenance"][point];
    EXPECT_EQ(entry["point"], point);
    EXPECT_EQ(entry["model_sha256"], Sha256Hex(ReadFile(model_)));
    EXPECT_NE(entry["resolved_scenario"].get<std::string>().find(point == 0 ? "kp = 4.0"
                                                                            : "kp = 8.5"),
              std::string::npos)
        << entry["resolved_scenario"];
  }
}

TEST_F(ProvenanceTest, AMissingModelNamesTheScenarioFileAndTheKey) {
  std::ofstream(dir_ / "moved.toml") << "cycles = 1\nmodel = \"models/none.xml\"\n";
  const CommandResult result = RunCli("run " + Quoted(dir_ / "moved.toml"));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find((dir_ / "moved.toml").string() + ":2: model: cannot open '" +
                               (dir_ / "models" / "none.xml").string() + "'"),
            std::string::npos)
      << result.output;
}

// Every version string is the CMake project version (CMakeLists.txt
// `project(ipmc_swim VERSION ...)`, passed to the tests as
// IPMC_SWIM_PROJECT_VERSION): the library's, the program's and
// `ipmc-swim --version`'s.
TEST(VersionTest, EveryVersionStringIsTheCMakeProjectVersion) {
  EXPECT_STREQ(Version(), IPMC_SWIM_PROJECT_VERSION);
  EXPECT_STREQ(ProgramVersion(), IPMC_SWIM_PROJECT_VERSION);
  const CommandResult printed = RunCli("--version");
  ASSERT_EQ(printed.exit_code, 0) << printed.output;
  EXPECT_EQ(printed.output, std::string("ipmc-swim ") + IPMC_SWIM_PROJECT_VERSION + "\n");
}

}  // namespace
}  // namespace ipmc
