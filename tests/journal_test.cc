// A sweep journal is verified before it is trusted (sim/batch/journal.h):
// every record carries a checksum over the sweep's fingerprint, its point
// and its row, so an edited number, a forged status or a record pasted
// from another sweep is an error naming its line; two different records
// of one point are an error; the header names the program version and a
// journal of another version is refused unless accepted; the journal is
// never written through a symbolic link.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/batch/journal.h"
#include "sim/batch/sweep.h"
#include "sim/core/data_paths.h"
#include "tests/cli_util.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::ReadFile;
using testing::WriteFile;


std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string Joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

// The message of what `open` throws, or "" if it does not.
template <typename Open>
std::string ErrorOf(Open open) {
  try {
    open();
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

class JournalTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = FreshDir(std::string("journal_") +
                    ::testing::UnitTest::GetInstance()->current_test_info()->name());
    WriteFile(dir_ / "fast.toml", testing::OneCycleScenario(0.5));
    const std::string sweep = (dir_ / "sweep.toml").string();
    WriteFile(sweep, "base = \"fast.toml\"\n[grid]\n\"controller.kp\" = [8.12, 4]\n");
    plan_ = LoadSweep(sweep);
    path_ = (dir_ / "table.journal").string();
    SweepJournal journal(path_, plan_);
    RunJournaledSweep(plan_, SweepOptions(), &journal);
    text_ = ReadFile(path_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Replaces the first `from` of line `index` (0: the header) by `to`.
  void EditLine(int index, const std::string& from, const std::string& to) {
    std::vector<std::string> lines = Lines(text_);
    const size_t at = lines.at(index).find(from);
    ASSERT_NE(at, std::string::npos) << lines.at(index);
    lines[index].replace(at, from.size(), to);
    WriteFile(path_, Joined(lines));
  }

  fs::path dir_;
  SweepPlan plan_;
  std::string path_;
  std::string text_;
};

TEST_F(JournalTest, AnUntouchedJournalResumesWithEveryRecord) {
  ASSERT_EQ(Lines(text_).size(), 3u);
  EXPECT_EQ(SweepJournal(path_, plan_).rows().size(), 2u);
  EXPECT_EQ(ReadSweepJournal(path_).header.program_version, ProgramVersion());
}

TEST_F(JournalTest, AnEditedNumberIsRefusedNamingItsLine) {
  // The last cell of point 1's row is a result; change its first digit.
  std::vector<std::string> lines = Lines(text_);
  const size_t end = lines[2].rfind("\"]");
  ASSERT_NE(end, std::string::npos) << lines[2];
  const size_t digit = lines[2].find_last_of("0123456789", end);
  lines[2][digit] = lines[2][digit] == '1' ? '2' : '1';
  WriteFile(path_, Joined(lines));
  const std::string error = ErrorOf([&] { SweepJournal journal(path_, plan_); });
  EXPECT_NE(error.find(path_ + ":3: the record of point 1 fails its checksum"), std::string::npos)
      << error;
  EXPECT_NE(ErrorOf([&] { ReadSweepJournal(path_); }).find(":3:"), std::string::npos);
}

TEST_F(JournalTest, AForgedStatusIsRefused) {
  EditLine(1, "\"ok\"", "\"failed\"");
  const std::string error = ErrorOf([&] { SweepJournal journal(path_, plan_); });
  EXPECT_NE(error.find(path_ + ":2: the record of point 0 fails its checksum"), std::string::npos)
      << error;
}

TEST_F(JournalTest, ARecordWithoutItsChecksumIsRefused) {
  std::vector<std::string> lines = Lines(text_);
  const size_t check = lines[1].find(",\"check\"");
  ASSERT_NE(check, std::string::npos) << lines[1];
  lines[1] = lines[1].substr(0, check) + "}";
  WriteFile(path_, Joined(lines));
  const std::string error = ErrorOf([&] { SweepJournal journal(path_, plan_); });
  EXPECT_NE(error.find(path_ + ":2: not a record of this journal's sweep"), std::string::npos)
      << error;
}

TEST_F(JournalTest, ARepeatedRecordIsKeptAndADifferentOneRefused) {
  std::vector<std::string> lines = Lines(text_);
  lines.push_back(lines[1]);
  WriteFile(path_, Joined(lines));
  EXPECT_EQ(SweepJournal(path_, plan_).rows().size(), 2u);

  // Point 1's record relabelled as point 0 (with a matching checksum,
  // as a journal written twice for one point would have) conflicts.
  const std::vector<std::string> original = Lines(text_);
  SweepJournal journal(path_, plan_);
  std::vector<std::string> row = journal.rows().at(1);
  row[0] = "0";
  // A second journal of the same plan writes a correctly signed record.
  const std::string other = (dir_ / "other.journal").string();
  {
    SweepJournal writer(other, plan_);
    writer.Record(row);
  }
  lines = original;
  lines.push_back(Lines(ReadFile(other)).at(1));
  journal.Remove();
  WriteFile(path_, Joined(lines));
  const std::string error = ErrorOf([&] { SweepJournal again(path_, plan_); });
  EXPECT_NE(error.find(path_ + ":4: a second, different record of point 0"), std::string::npos)
      << error;
}

TEST_F(JournalTest, AnotherProgramVersionIsRefusedUnlessAccepted) {
  const std::string version = std::string("\"program_version\":\"") + ProgramVersion() + "\"";
  EditLine(0, version, "\"program_version\":\"0.0.1\"");
  const std::string error = ErrorOf([&] { SweepJournal journal(path_, plan_); });
  EXPECT_NE(error.find(path_ + ": written by ipmc-swim 0.0.1, this is " + ProgramVersion()),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("--resume-other-version"), std::string::npos) << error;
  EXPECT_EQ(SweepJournal(path_, plan_, /*accept_other_version=*/true).rows().size(), 2u);
}

TEST_F(JournalTest, AnOlderFormatIsRefusedByName) {
  EditLine(0, "\"ipmc_swim_sweep_journal\":2", "\"ipmc_swim_sweep_journal\":1");
  const std::string error = ErrorOf([&] { SweepJournal journal(path_, plan_); });
  EXPECT_NE(error.find(path_ + ":1: a sweep journal of format 1, this program reads format 2"),
            std::string::npos)
      << error;
}

TEST_F(JournalTest, ASymbolicLinkIsNeverWrittenThrough) {
  const fs::path target = dir_ / "precious.txt";
  WriteFile(target, "keep me\n");
  const std::string link = (dir_ / "linked.journal").string();
  fs::create_symlink(target, link);
  const std::string error = ErrorOf([&] { SweepJournal journal(link, plan_); });
  EXPECT_NE(error.find(link + ": is a symbolic link"), std::string::npos) << error;
  EXPECT_EQ(ReadFile(target), "keep me\n");
  // A dangling link is refused too, and creates nothing where it points.
  const fs::path nowhere = dir_ / "nowhere.txt";
  const std::string dangling = (dir_ / "dangling.journal").string();
  fs::create_symlink(nowhere, dangling);
  EXPECT_NE(ErrorOf([&] { SweepJournal journal(dangling, plan_); }).find("is a symbolic link"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(nowhere));
}

}  // namespace
}  // namespace ipmc
