// Slurm job scripts without a cluster: the options are checked (array
// size, time limit, partition, sbatch on the PATH, a directory of another
// sweep) with one-line errors and nothing written or submitted; the
// scripts, run the way Slurm runs them (SLURM_ARRAY_TASK_ID and
// SLURM_CPUS_PER_TASK set), give the table of a local run; submission
// passes the array's id to the merge job's dependency (a stand-in sbatch
// records its arguments). tests/slurm/slurm_sweep_test.sh runs the same
// on a real cluster.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "sim/batch/slurm.h"
#include "sim/batch/sweep.h"
#include "tests/cli_util.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;
using testing::CountLines;
using testing::RunCli;
using testing::ReadFile;
using testing::WriteFile;

const fs::path kSourceDir = IPMC_SWIM_SOURCE_DIR;

std::string TimeError(const std::string& text) {
  try {
    ParseSlurmTimeLimit(text);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "no error";
}

TEST(SlurmTimeLimitTest, SlurmsFormatsInMinutes) {
  EXPECT_EQ(ParseSlurmTimeLimit("90"), 90);
  EXPECT_EQ(ParseSlurmTimeLimit("1:30"), 2);  // 1 min 30 s, rounded up
  EXPECT_EQ(ParseSlurmTimeLimit("1:30:00"), 90);
  EXPECT_EQ(ParseSlurmTimeLimit("2-00"), 2880);
  EXPECT_EQ(ParseSlurmTimeLimit("1-2:03"), 1563);
  EXPECT_EQ(ParseSlurmTimeLimit("1-0:0:30"), 1441);
  EXPECT_EQ(ParseSlurmTimeLimit("INFINITE"), -1);
  EXPECT_EQ(TimeError("1h"),
            "sweep: --time must be a Slurm time limit > 0 (M, M:S, H:M:S, D-H, D-H:M or D-H:M:S, "
            "or INFINITE; got '1h')");
  for (const char* bad : {"", "0", "0:00", "1:2:3:4", "-5", "1-2-3", "a:b", "1:", "1.5"}) {
    EXPECT_NE(TimeError(bad).find("got '" + std::string(bad) + "'"), std::string::npos) << bad;
  }
}

class SlurmJobTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::FreshDir(std::string("slurm_") +
                             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    WriteFile(dir_ / "fast.toml",
              "model = \"" + (kSourceDir / "models" / "flagellum3.xml").string() +
                  "\"\ncycles = 1\ntimestep_s = 5e-4\n[waveform]\nfrequency_Hz = 0.5\n");
    sweep_ = (dir_ / "sweep.toml").string();
    WriteFile(sweep_,
              "base = \"fast.toml\"\n[grid]\n\"controller.kp\" = [8.12, 4, 2, 1, 0.5]\n");
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A one-line error, exit code 1 (2 for the option parser's own), and
  // no job script.
  void ExpectRefused(const std::string& args, const std::string& message,
                     const std::string& prefix = "", int exit_code = 1) const {
    const testing::CommandResult result = RunCli(args, prefix);
    EXPECT_EQ(result.exit_code, exit_code) << result.output;
    EXPECT_EQ(CountLines(result.output), 1) << result.output;
    EXPECT_NE(result.output.find(message), std::string::npos) << result.output;
    EXPECT_FALSE(fs::exists(dir_ / "job" / "sweep.sbatch")) << args;
  }

  fs::path dir_;
  std::string sweep_;
};

TEST_F(SlurmJobTest, BadOptionsAreOneLineErrorsAndNothingIsWritten) {
  const std::string job = " --slurm " + (dir_ / "job").string();
  ExpectRefused("sweep " + sweep_ + job + " --array-size 6 --dry-run",
                "sweep: --array-size must be in [1, 5] (the sweep's points; got 6)");
  ExpectRefused("sweep " + sweep_ + job + " --array-size -1 --dry-run",
                "--array-size must be in [1, 5]");
  ExpectRefused("sweep " + sweep_ + job + " --time 2h --dry-run",
                "sweep: --time must be a Slurm time limit > 0");
  ExpectRefused("sweep " + sweep_ + job + " --cpus-per-task 0 --dry-run",
                "sweep: --cpus-per-task must be >= 1 (got 0)");
  ExpectRefused("sweep " + sweep_ + job + " --partition 'a b' --dry-run",
                "sweep: --partition must be a partition name");
  ExpectRefused("sweep " + sweep_ + " --slurm '" + (dir_ / "my job").string() + "' --dry-run",
                "has a space, quote, backslash or %");
  EXPECT_FALSE(fs::exists(dir_ / "my job"));
  ExpectRefused("sweep " + sweep_ + job + " --out x", "--out excludes --slurm", "", 2);
  ExpectRefused("sweep " + sweep_ + " --array-size 2", "--array-size requires --slurm", "", 2);
  // Submitting needs sbatch; PATH holds only an empty directory here.
  fs::create_directories(dir_ / "empty");
  ExpectRefused("sweep " + sweep_ + job, "sweep --slurm: sbatch is not on the PATH",
                "PATH=" + (dir_ / "empty").string() + " ");
  EXPECT_FALSE(fs::exists(dir_ / "job"));
}

TEST_F(SlurmJobTest, TheScriptsRunAsSlurmRunsThemGiveTheLocalTable) {
  const fs::path job = dir_ / "job";
  const testing::CommandResult written =
      RunCli("sweep " + sweep_ + " --slurm " + job.string() +
             " --array-size 2 --cpus-per-task 2 --time 1:00:00 --partition short --dry-run");
  ASSERT_EQ(written.exit_code, 0) << written.output;
  EXPECT_NE(written.output.find("(2 tasks of 5 points, 2 CPUs each)"), std::string::npos)
      << written.output;
  EXPECT_NE(written.output.find("dry run, nothing submitted"), std::string::npos);
  const std::string array = ReadFile(job / "sweep.sbatch");
  for (const std::string& line :
       {std::string("#SBATCH --array=1-2\n"), std::string("#SBATCH --cpus-per-task=2\n"),
        std::string("#SBATCH --time=1:00:00\n"), std::string("#SBATCH --partition=short\n"),
        "#SBATCH --output=" + job.string() + "/logs/sweep_%A_%a.out\n",
        std::string("--shard \"$shard/2\" --jobs \"${SLURM_CPUS_PER_TASK:-1}\"")}) {
    EXPECT_NE(array.find(line), std::string::npos) << line << "\n" << array;
  }
  const std::string merge = ReadFile(job / "merge.sbatch");
  EXPECT_NE(merge.find("merge --partial --out '" + job.string() + "/table'"), std::string::npos)
      << merge;
  EXPECT_NE(merge.find("'" + job.string() + "/shards/shard_2.csv'"), std::string::npos) << merge;
  EXPECT_TRUE(fs::exists(job / "shards" / "shard_1.journal"));
  EXPECT_TRUE(fs::exists(job / "logs"));
  const testing::CommandResult status = RunCli("sweep --status " + job.string());
  EXPECT_NE(status.output.find("missing: 5 (0-4)"), std::string::npos) << status.output;

  // Slurm's way: each task with its SLURM_ARRAY_TASK_ID, then the merge.
  for (const char* task : {"2", "1"}) {
    const std::string command = "SLURM_ARRAY_TASK_ID=" + std::string(task) +
                                " SLURM_CPUS_PER_TASK=2 bash " + (job / "sweep.sbatch").string() +
                                " > /dev/null 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << task;
  }
  EXPECT_EQ(LoadSweepTableCsv((job / "shards" / "shard_2.csv").string()).rows.size(), 2u);
  ASSERT_EQ(std::system(("bash " + (job / "merge.sbatch").string() + " > /dev/null").c_str()), 0);
  const std::string local = (dir_ / "local").string();
  ASSERT_EQ(RunCli("sweep " + sweep_ + " --jobs 1 --out " + local).exit_code, 0);
  EXPECT_EQ(ReadFile(job / "table.csv"), ReadFile(local + ".csv"));
  EXPECT_EQ(ReadFile(job / "table.json"), ReadFile(local + ".json"));

  // The directory is this sweep's: another one is refused, nothing overwritten.
  WriteFile(dir_ / "other.toml", "base = \"fast.toml\"\n[grid]\n\"controller.kp\" = [3, 4]\n");
  const std::string journal = ReadFile(job / "shards" / "shard_1.journal");
  const testing::CommandResult refused = RunCli(
      "sweep " + (dir_ / "other.toml").string() + " --slurm " + job.string() + " --dry-run");
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_EQ(CountLines(refused.output), 1) << refused.output;
  EXPECT_NE(refused.output.find((job / "shards" / "shard_1.journal").string() +
                                ": records another sweep"),
            std::string::npos)
      << refused.output;
  EXPECT_EQ(ReadFile(job / "sweep.sbatch"), array);
  EXPECT_EQ(ReadFile(job / "shards" / "shard_1.journal"), journal);
}

TEST_F(SlurmJobTest, SubmissionChainsTheMergeJobAfterTheArray) {
  // A stand-in sbatch: records its arguments, answers job ids 4242, 4243.
  const fs::path bin = dir_ / "bin";
  fs::create_directories(bin);
  const fs::path calls = dir_ / "calls.txt";
  WriteFile(bin / "sbatch",
            "#!/bin/sh\necho \"sbatch $*\" >> " + calls.string() +
                "\nn=$(wc -l < " + calls.string() + ")\necho $((4241 + n))\n");
  WriteFile(bin / "scancel", "#!/bin/sh\necho \"scancel $*\" >> " + calls.string() + "\n");
  fs::permissions(bin / "sbatch", fs::perms::owner_all);
  fs::permissions(bin / "scancel", fs::perms::owner_all);
  const std::string path = "PATH=" + bin.string() + ":/usr/bin:/bin ";
  const fs::path job = dir_ / "job";
  const testing::CommandResult submitted =
      RunCli("sweep " + sweep_ + " --slurm " + job.string(), path);
  ASSERT_EQ(submitted.exit_code, 0) << submitted.output;
  EXPECT_NE(submitted.output.find("submitted job array 4242 and merge job 4243"), std::string::npos)
      << submitted.output;
  EXPECT_NE(ReadFile(job / "sweep.sbatch").find("#SBATCH --array=1-5\n"), std::string::npos);
  EXPECT_EQ(ReadFile(calls), "sbatch --parsable " + (job / "sweep.sbatch").string() +
                                 "\nsbatch --parsable --dependency=afterany:4242 " +
                                 (job / "merge.sbatch").string() + "\n");

  // sbatch refusing the merge job: its message, and the array cancelled.
  fs::remove(calls);
  WriteFile(bin / "sbatch",
            "#!/bin/sh\necho \"sbatch $*\" >> " + calls.string() +
                "\nif [ $(wc -l < " + calls.string() +
                ") -gt 1 ]; then echo 'sbatch: error: Batch job submission failed: Invalid "
                "dependency' >&2; exit 1; fi\necho 77\n");
  const testing::CommandResult refused =
      RunCli("sweep " + sweep_ + " --slurm " + job.string(), path);
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_EQ(CountLines(refused.output), 1) << refused.output;
  EXPECT_NE(refused.output.find("sbatch refused the merge job: sbatch: error: Batch job submission "
                                "failed: Invalid dependency (job array 77 cancelled)"),
            std::string::npos)
      << refused.output;
  EXPECT_NE(ReadFile(calls).find("scancel 77\n"), std::string::npos);
}

}  // namespace
}  // namespace ipmc
