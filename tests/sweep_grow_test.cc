// A sweep whose grid gains values, run again into the prefix of its
// finished table, runs only the new points and gives the table the whole
// sweep would, byte for byte (sim/batch/sweep_grow.h); a changed base or a
// table of another program version is still refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <string>

#include "sim/batch/sweep_command.h"
#include "tests/cli_util.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::ReadFile;
using testing::WriteFile;

class SweepGrowTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = FreshDir(std::string("sweep_grow_") +
                    ::testing::UnitTest::GetInstance()->current_test_info()->name());
    WriteFile(dir_ / "fast.toml", testing::OneCycleScenario(0.5));
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A sweep file over kp (first key, outermost) and ki.
  std::string Sweep(const std::string& name, const std::string& kp, const std::string& base) {
    const std::string path = (dir_ / (name + ".toml")).string();
    WriteFile(path, "base = \"" + base + "\"\n[grid]\n\"controller.kp\" = " + kp +
                        "\n\"controller.ki\" = [40, 50, 53.36, 60]\n");
    return path;
  }

  // Runs `sweep` into `out`; returns the points it ran.
  int Run(const std::string& sweep, const std::string& out) {
    SweepCommand command;
    command.sweep = sweep;
    command.out = (dir_ / out).string();
    command.jobs = 2;
    SweepCommandRun run(PlanSweepCommand(command));
    int ran = 0;
    const SweepCommandOutcome outcome = run.Run([&](const SweepProgress&) { ++ran; }, {});
    EXPECT_TRUE(outcome.complete);
    return ran;
  }

  fs::path dir_;
};

TEST_F(SweepGrowTest, AGridOf20GrownTo24Runs4AndGivesTheWholeSweepsTable) {
  const std::string small = Sweep("sweep", "[4, 6, 8.12, 10, 12]", "fast.toml");
  EXPECT_EQ(Run(small, "table"), 20);
  // kp gains a value in the middle: the points after it move to new indices.
  const std::string grown = Sweep("sweep", "[4, 6, 7, 8.12, 10, 12]", "fast.toml");
  EXPECT_EQ(Run(grown, "table"), 4);
  EXPECT_EQ(Run(Sweep("whole", "[4, 6, 7, 8.12, 10, 12]", "fast.toml"), "whole"), 24);
  EXPECT_EQ(ReadFile(dir_ / "table.csv"), ReadFile(dir_ / "whole.csv"));
  EXPECT_EQ(ReadFile(dir_ / "table.json"), ReadFile(dir_ / "whole.json"));
  // Run again: the journal now records the grown sweep, nothing runs.
  EXPECT_EQ(Run(grown, "table"), 0);
}

TEST_F(SweepGrowTest, AChangedBaseOrAnotherVersionsTableIsStillRefused) {
  EXPECT_EQ(Run(Sweep("sweep", "[4, 8.12]", "fast.toml"), "table"), 8);
  WriteFile(dir_ / "slow.toml", testing::OneCycleScenario(0.25));
  const std::string changed = Sweep("sweep", "[4, 8.12, 10]", "slow.toml");
  SweepCommand command;
  command.sweep = changed;
  command.out = (dir_ / "table").string();
  try {
    SweepCommandRun run(PlanSweepCommand(command));
    ADD_FAILURE() << "a changed base was accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("records another sweep"), std::string::npos)
        << error.what();
  }
  // The same grown grid on the same base, but the table says another
  // program made it: refused as well.
  std::string json = ReadFile(dir_ / "table.json");
  const std::string version = "\"program_version\": \"";
  json.insert(json.find(version) + version.size(), "0.0.");
  WriteFile(dir_ / "table.json", json);
  command.sweep = Sweep("sweep", "[4, 8.12, 10]", "fast.toml");
  EXPECT_THROW(SweepCommandRun run(PlanSweepCommand(command)), std::runtime_error);
}

}  // namespace
}  // namespace ipmc
