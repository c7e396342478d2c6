// Resuming sweeps: a sweep killed midway (SIGKILL) or stopped by SIGINT
// goes on from its journal and writes the table of an uninterrupted run
// byte for byte; a journal of another sweep is refused; a torn last
// record is dropped; merge --partial and sweep --status report what
// exists and what is missing; the default --jobs follows the affinity
// mask.
#include <gtest/gtest.h>
#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "sim/batch/cpu_affinity.h"
#include "sim/batch/journal.h"
#include "sim/batch/sweep.h"
#include "sim/batch/sweep_status.h"
#include "tests/cli_util.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;
using testing::CountLines;
using testing::FreshDir;
using testing::RunCli;
using testing::ReadFile;
using testing::WriteFile;


// Eight points of 0.2 Hz waves (5 s, 10000 steps, about 0.2 s each):
// long enough to be killed in the middle.
constexpr char kSlowSweep[] =
    "base = \"slow.toml\"\n"
    "[grid]\n"
    "\"waveform.frequency_Hz\" = [0.2, 0.22]\n"
    "actuation = [\"single\", \"distributed\"]\n"
    "\"controller.kp\" = [8.12, 4]\n";

// Journal records (lines after the header) written so far.
int Records(const fs::path& journal) {
  const int lines = CountLines(ReadFile(journal));
  return lines > 0 ? lines - 1 : 0;
}

// `ipmc-swim ARGS`, started in the background with its output in `log`.
pid_t StartCli(const std::vector<std::string>& args, const fs::path& log) {
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string log_path = log.string();
    if (!freopen(log_path.c_str(), "w", stdout) || !freopen(log_path.c_str(), "a", stderr)) _exit(127);
    setvbuf(stdout, nullptr, _IONBF, 0);
    std::vector<char*> argv = {const_cast<char*>(IPMC_SWIM_CLI)};
    for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
    argv.push_back(nullptr);
    execv(IPMC_SWIM_CLI, argv.data());
    _exit(127);
  }
  return pid;
}

// Waits until the journal holds `records` records (or 60 s pass).
bool WaitForRecords(const fs::path& journal, int records) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    if (fs::exists(journal) && Records(journal) >= records) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

int WaitForExit(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class ResumeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = FreshDir(std::string("resume_") +
                    ::testing::UnitTest::GetInstance()->current_test_info()->name());
    WriteFile(dir_ / "slow.toml", testing::OneCycleScenario(0.2));
    WriteFile(dir_ / "fast.toml", testing::OneCycleScenario(0.5));
    sweep_ = (dir_ / "sweep.toml").string();
    WriteFile(sweep_, kSlowSweep);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The uninterrupted run's table (CSV and JSON).
  std::pair<std::string, std::string> Uninterrupted() const {
    const std::string out = (dir_ / "whole" / "table").string();
    const testing::CommandResult whole = RunCli("sweep " + sweep_ + " --jobs 2 --out " + out);
    EXPECT_EQ(whole.exit_code, 0) << whole.output;
    return {ReadFile(out + ".csv"), ReadFile(out + ".json")};
  }

  fs::path dir_;
  std::string sweep_;
};

TEST_F(ResumeTest, SigkillMidwayLosesOnlyThePointsInFlightAndTheResumedTableIsTheSame) {
  const std::string out = (dir_ / "killed" / "table").string();
  const fs::path journal = out + ".journal";
  const pid_t pid = StartCli({"sweep", sweep_, "--jobs", "2", "--out", out}, dir_ / "killed.log");
  ASSERT_TRUE(WaitForRecords(journal, 3)) << ReadFile(dir_ / "killed.log");
  kill(pid, SIGKILL);
  EXPECT_EQ(WaitForExit(pid), 128 + SIGKILL);
  const int recorded = Records(journal);
  ASSERT_GE(recorded, 3);
  ASSERT_LT(recorded, 8) << "the sweep ended before it was killed";
  EXPECT_FALSE(fs::exists(out + ".csv"));
  // Every record that made it is whole (the kill may tear only a last one).
  EXPECT_EQ(static_cast<int>(ReadSweepJournal(journal.string()).rows.size()), recorded);

  const testing::CommandResult resumed = RunCli("sweep " + sweep_ + " --jobs 2 --out " + out);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("resuming from " + journal.string() + ": " +
                                std::to_string(recorded) + " of 8 points done before"),
            std::string::npos)
      << resumed.output;
  // Only the other points ran: "run k/n done" with n = 8 - recorded.
  const std::string remaining = std::to_string(8 - recorded);
  EXPECT_NE(resumed.output.find("run " + remaining + "/" + remaining + " done"), std::string::npos)
      << resumed.output;
  EXPECT_EQ(resumed.output.find("run " + std::to_string(9 - recorded) + "/"), std::string::npos)
      << resumed.output;
  EXPECT_EQ(Records(journal), 8);

  const auto [csv, json] = Uninterrupted();
  EXPECT_EQ(ReadFile(out + ".csv"), csv);
  EXPECT_EQ(ReadFile(out + ".json"), json);
  // Once complete, running it again runs nothing and writes the same table.
  const testing::CommandResult again = RunCli("sweep " + sweep_ + " --jobs 1 --out " + out);
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(again.output.find(" done (point"), std::string::npos) << again.output;
  EXPECT_EQ(ReadFile(out + ".csv"), csv);
}

TEST_F(ResumeTest, SigintStopsAtAPointBoundaryAndSaysHowToResume) {
  const std::string out = (dir_ / "stopped" / "table").string();
  const fs::path journal = out + ".journal";
  const fs::path log = dir_ / "stopped.log";
  const pid_t pid = StartCli({"sweep", sweep_, "--jobs", "2", "--out", out}, log);
  ASSERT_TRUE(WaitForRecords(journal, 1)) << ReadFile(log);
  kill(pid, SIGINT);
  EXPECT_EQ(WaitForExit(pid), 130) << ReadFile(log);
  const std::string output = ReadFile(log);
  EXPECT_NE(output.find("run the same command again to resume"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(out + ".csv"));
  // The points running when SIGINT came finished and were recorded: the
  // journal holds exactly the points reported done, and ends on a whole line.
  const std::string text = ReadFile(journal);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  int reported = 0;
  for (std::string::size_type at = output.find(" done (point"); at != std::string::npos;
       at = output.find(" done (point", at + 1)) {
    ++reported;
  }
  EXPECT_EQ(Records(journal), reported) << output;
  EXPECT_LT(reported, 8) << output;

  const testing::CommandResult resumed = RunCli("sweep " + sweep_ + " --jobs 2 --out " + out);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  const auto [csv, json] = Uninterrupted();
  EXPECT_EQ(ReadFile(out + ".csv"), csv);
  EXPECT_EQ(ReadFile(out + ".json"), json);
}

TEST_F(ResumeTest, AJournalOfAnotherSweepIsRefusedAndLeftAlone) {
  const std::string sweep = (dir_ / "fast_sweep.toml").string();
  WriteFile(sweep, "base = \"fast.toml\"\n[grid]\ncycles = [1]\n");
  const std::string out = (dir_ / "out" / "table").string();
  ASSERT_EQ(RunCli("sweep " + sweep + " --out " + out).exit_code, 0);
  const std::string journal = ReadFile(out + ".journal");
  const std::string table = ReadFile(out + ".csv");

  // The same points with a comment added: the same sweep.
  const SweepPlan plan = LoadSweep(sweep);
  WriteFile(sweep, "# one point\nbase = \"fast.toml\"\n[grid]\ncycles = [1]\n");
  EXPECT_EQ(SweepFingerprint(LoadSweep(sweep)), SweepFingerprint(plan));
  // A value of the base changes every point.
  WriteFile(dir_ / "fast.toml", testing::OneCycleScenario(0.25));
  EXPECT_NE(SweepFingerprint(LoadSweep(sweep)), SweepFingerprint(plan));

  const testing::CommandResult refused = RunCli("sweep " + sweep + " --out " + out);
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_EQ(CountLines(refused.output), 1) << refused.output;
  EXPECT_NE(refused.output.find(out + ".journal: records another sweep"), std::string::npos)
      << refused.output;
  EXPECT_EQ(ReadFile(out + ".journal"), journal);
  EXPECT_EQ(ReadFile(out + ".csv"), table);
}

TEST_F(ResumeTest, ATornLastRecordIsDroppedAndTheJournalGoesOn) {
  const SweepPlan plan = ParseSweep(
      "base = \"fast.toml\"\n[grid]\n\"controller.kp\" = [8.12, 4, 2]\n", sweep_);
  const std::string path = (dir_ / "j" / "table.journal").string();
  SweepOptions options;
  int runs = 0;
  options.on_point_done = [&](const SweepProgress&) { ++runs; };
  options.stop_requested = [&] { return runs >= 2; };
  {
    SweepJournal journal(path, plan);
    const JournaledSweep first = RunJournaledSweep(plan, options, &journal);
    EXPECT_FALSE(first.Complete());
    EXPECT_EQ(first.table.rows.size(), 2u);
  }
  std::ofstream(path, std::ios::app) << "{\"point\": 2, \"row\": [\"2\", \"2\", \"o";
  EXPECT_EQ(ReadSweepJournal(path).rows.size(), 2u);

  runs = 0;
  options.stop_requested = nullptr;
  SweepJournal journal(path, plan);
  EXPECT_EQ(journal.rows().size(), 2u);
  const JournaledSweep second = RunJournaledSweep(plan, options, &journal);
  EXPECT_TRUE(second.Complete());
  EXPECT_EQ(second.resumed, 2);
  EXPECT_EQ(runs, 1);
  EXPECT_EQ(ReadSweepJournal(path).rows.size(), 3u);
  EXPECT_EQ(SweepTableCsv(second.table), SweepTableCsv(RunSweep(plan, SweepOptions())));

  // Two sweeps cannot hold one journal.
  try {
    SweepJournal other(path, plan);
    ADD_FAILURE() << "a second holder of the journal";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("in use by another running sweep"), std::string::npos)
        << error.what();
  }
}

TEST_F(ResumeTest, PartialMergeAndStatusListWhatIsMissing) {
  // Six points, the fourth refused by the scenario reader (recorded as failed).
  const std::string sweep = (dir_ / "six.toml").string();
  WriteFile(sweep,
            "base = \"fast.toml\"\n"
            "[[point]]\ncontroller.kp = 8.12\n[[point]]\ncontroller.kp = 4.0\n"
            "[[point]]\ncontroller.kp = 2.0\n[[point]]\nwaveform.frequency_Hz = 0\n"
            "[[point]]\ncontroller.kp = 1.0\n[[point]]\ncontroller.kp = 0.5\n");
  const fs::path shards = dir_ / "run" / "shards";
  const std::string whole = (dir_ / "whole").string();
  ASSERT_EQ(RunCli("sweep " + sweep + " --jobs 2 --out " + whole).exit_code, 0);
  for (const char* shard : {"1", "2"}) {
    const testing::CommandResult run =
        RunCli("sweep " + sweep + " --shard " + shard + "/3 --out " +
               (shards / ("shard_" + std::string(shard))).string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
  }
  // Shard 3 (points 2 and 5) stopped after its first point.
  const SweepPlan plan = LoadSweep(sweep);
  SweepOptions options;
  options.shard = ParseSweepShard("3/3");
  bool stop = false;
  options.on_point_done = [&](const SweepProgress&) { stop = true; };
  options.stop_requested = [&] { return stop; };
  {
    SweepJournal journal((shards / "shard_3.journal").string(), plan);
    ASSERT_EQ(RunJournaledSweep(plan, options, &journal).table.rows.size(), 1u);
  }
  std::string tables;
  for (const char* shard : {"1", "2", "3"}) {
    tables += " " + (shards / ("shard_" + std::string(shard) + ".csv")).string();
  }
  const std::string merged = (dir_ / "merged").string();
  const testing::CommandResult strict = RunCli("merge --out " + merged + tables);
  EXPECT_EQ(strict.exit_code, 1);
  EXPECT_EQ(CountLines(strict.output), 1) << strict.output;
  EXPECT_NE(strict.output.find((shards / "shard_3.csv").string() + " does not exist"),
            std::string::npos)
      << strict.output;
  EXPECT_FALSE(fs::exists(merged + ".csv"));

  const testing::CommandResult partial = RunCli("merge --partial --out " + merged + tables);
  ASSERT_EQ(partial.exit_code, 0) << partial.output;
  EXPECT_NE(partial.output.find((shards / "shard_3.csv").string() + ": not written; 1 points from " +
                                (shards / "shard_3.journal").string()),
            std::string::npos)
      << partial.output;
  EXPECT_NE(partial.output.find("5 of 6 points merged"), std::string::npos) << partial.output;
  EXPECT_NE(partial.output.find("missing: 1 (5)"), std::string::npos) << partial.output;
  // The rows that exist are the whole run's rows.
  SweepTable expected = LoadSweepTableCsv(whole + ".csv");
  expected.rows.erase(expected.rows.begin() + 5);
  EXPECT_EQ(SweepTableCsv(LoadSweepTableCsv(merged + ".csv")), SweepTableCsv(expected));

  const testing::CommandResult status = RunCli("sweep --status " + (dir_ / "run").string());
  ASSERT_EQ(status.exit_code, 0) << status.output;
  EXPECT_NE(status.output.find(sweep + ": 6 points, 3 journals"), std::string::npos) << status.output;
  EXPECT_NE(status.output.find("done:    4 (0-2, 4)\n"), std::string::npos) << status.output;
  EXPECT_NE(status.output.find("failed:  1 (3)\n  point 3: " + sweep +
                               ":9: waveform: frequency_Hz must be finite and != 0 (got 0)\n"),
            std::string::npos)
      << status.output;
  EXPECT_NE(status.output.find("missing: 1 (5)\n"), std::string::npos) << status.output;
  const testing::CommandResult nothing = RunCli("sweep --status " + (dir_ / "none").string());
  EXPECT_EQ(nothing.exit_code, 1);
  EXPECT_NE(nothing.output.find("no sweep journal here"), std::string::npos) << nothing.output;
}

// The CPUs of the affinity mask, counted from /proc/self/status's
// Cpus_allowed_list ("0-3,6"): an independent reading of the same mask.
int CpusAllowedByProc() {
  std::ifstream status("/proc/self/task/" + std::to_string(gettid()) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("Cpus_allowed_list:", 0) != 0) continue;
    std::istringstream list(line.substr(line.find(':') + 1));
    int count = 0;
    std::string range;
    while (std::getline(list, range, ',')) {
      const auto dash = range.find('-');
      count += dash == std::string::npos ? 1 : std::stoi(range.substr(dash + 1)) -
                                                   std::stoi(range.substr(0, dash)) + 1;
    }
    return count;
  }
  return -1;
}

TEST(CpuAffinityTest, TheDefaultJobsAreTheCpusTheProcessMayUse) {
  EXPECT_EQ(AvailableCpus(), CpusAllowedByProc());
  cpu_set_t all;
  ASSERT_EQ(sched_getaffinity(0, sizeof(all), &all), 0);
  int first = 0;
  while (!CPU_ISSET(first, &all)) ++first;
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(first, &one);
  ASSERT_EQ(sched_setaffinity(0, sizeof(one), &one), 0);
  EXPECT_EQ(AvailableCpus(), 1);
  EXPECT_EQ(CpusAllowedByProc(), 1);
  ASSERT_EQ(sched_setaffinity(0, sizeof(all), &all), 0);
  // The program under taskset: one CPU, one job by default.
  const testing::CommandResult help = RunCli("sweep --help | grep -- --jobs");
  const testing::CommandResult pinned =
      testing::RunCli("sweep --help | grep -- --jobs", "taskset -c " + std::to_string(first) + " ");
  EXPECT_NE(pinned.output.find("--jobs INT=1 "), std::string::npos) << pinned.output;
  EXPECT_NE(help.output.find("--jobs INT=" + std::to_string(CpusAllowedByProc()) + " "),
            std::string::npos)
      << help.output;
}

}  // namespace
}  // namespace ipmc
