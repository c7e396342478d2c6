// The output-file helper: complete files with the mode a new file gets
// under the umask, or no file and the reason.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <linux/fs.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <vector>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "sim/core/data_paths.h"
#include "sim/io/files.h"

namespace ipmc::testing {
namespace {

namespace fs = std::filesystem;

fs::path ScratchDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("ipmc_files_test_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

mode_t ModeOf(const fs::path& path) {
  struct stat info {};
  EXPECT_EQ(stat(path.c_str(), &info), 0);
  return info.st_mode & 0777;
}

TEST(FilesTest, WrittenFileHasItsContentAndTheUmasksMode) {
  const fs::path dir = ScratchDir("mode");
  for (const mode_t mask : {mode_t{022}, mode_t{027}, mode_t{077}}) {
    const mode_t previous = umask(mask);
    const fs::path path = dir / ("out_" + std::to_string(mask) + ".txt");
    WriteFileAtomically(path.string(), "a,b\n1,2\n");
    umask(previous);
    EXPECT_EQ(ReadAll(path), "a,b\n1,2\n");
    // open(2) with 0666 gives 0644, 0640 and 0600 under these masks.
    EXPECT_EQ(ModeOf(path), 0666 & ~mask) << "umask " << mask;
  }
  fs::remove_all(dir);
}

TEST(FilesTest, ReplacesAnExistingFileWhole) {
  const fs::path dir = ScratchDir("replace");
  const fs::path path = dir / "table.csv";
  WriteFileAtomically(path.string(), std::string(10000, 'x'));
  WriteFileAtomically(path.string(), "short\n");
  EXPECT_EQ(ReadAll(path), "short\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);
  fs::remove_all(dir);
}

TEST(FilesTest, FailureNamesThePathAndTheReasonAndLeavesNothing) {
  const fs::path dir = ScratchDir("missing");
  const fs::path path = dir / "no_such_folder" / "out.csv";
  try {
    WriteFileAtomically(path.string(), "x");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 0);
  fs::remove_all(dir);
}

TEST(FilesTest, BuildTreeProgramUsesTheSourceTreesModelsAndScenarios) {
  // The test runs from the build tree, where no share/ipmc_swim exists.
  EXPECT_EQ(fs::path(ModelsDir()), fs::path(IPMC_SWIM_SOURCE_DIR) / "models");
  EXPECT_EQ(fs::path(ScenariosDir()), fs::path(IPMC_SWIM_SOURCE_DIR) / "scenarios");
  EXPECT_TRUE(fs::exists(fs::path(ModelsDir()) / "flagellum3.xml"));
}

// The names in `dir`, sorted.
std::vector<std::string> Entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(FilesTest, FilesWrittenTogetherReplaceTheOldSetAndRemoveItsStaleFiles) {
  const fs::path dir = ScratchDir("together");
  const std::string a = (dir / "a.csv").string(), b = (dir / "b.json").string();
  const std::string extra = (dir / "run.mat").string();
  WriteFilesTogether({{a, "old a"}, {b, "old b"}, {extra, "old mat"}});
  WriteFilesTogether({{a, "new a"}, {b, "new b"}}, {extra});
  EXPECT_EQ(ReadAll(a), "new a");
  EXPECT_EQ(ReadAll(b), "new b");
  // The stale file is gone, and no temporary or kept copy is left.
  EXPECT_EQ(Entries(dir), (std::vector<std::string>{"a.csv", "b.json"}));
  fs::remove_all(dir);
}

TEST(FilesTest, ADirectoryInTheWayChangesNothing) {
  const fs::path dir = ScratchDir("in_the_way");
  const std::string a = (dir / "a.csv").string();
  WriteFileAtomically(a, "old a");
  fs::create_directories(dir / "summary.json");
  try {
    WriteFilesTogether({{a, "new a"}, {(dir / "summary.json").string(), "{}"}});
    FAIL() << "a directory was replaced";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("summary.json: cannot replace it, it is a directory"),
              std::string::npos)
        << error.what();
  }
  EXPECT_EQ(ReadAll(a), "old a");
  EXPECT_EQ(Entries(dir), (std::vector<std::string>{"a.csv", "summary.json"}));
  fs::remove_all(dir);
}

// Sets or clears the immutable flag of `path` (chattr +i / -i); false if
// the file system or the process's privileges do not allow it.
bool SetImmutable(const fs::path& path, bool immutable) {
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  int flags = 0;
  bool done = ioctl(fd, FS_IOC_GETFLAGS, &flags) == 0;
  flags = immutable ? flags | FS_IMMUTABLE_FL : flags & ~FS_IMMUTABLE_FL;
  done = done && ioctl(fd, FS_IOC_SETFLAGS, &flags) == 0;
  close(fd);
  return done;
}

TEST(FilesTest, AFileThatCannotBeReplacedChangesNothing) {
  const fs::path dir = ScratchDir("restore");
  const std::string a = (dir / "a.csv").string(), b = (dir / "b.csv").string();
  const std::string last = (dir / "summary.json").string(), stale = (dir / "run.mat").string();
  WriteFilesTogether({{a, "old a"}, {b, "old b"}, {last, "old summary"}, {stale, "old mat"}});
  // An immutable summary cannot be replaced, even by root: found before
  // the first file is renamed, so the old set stays whole.
  if (!SetImmutable(last, true)) {
    fs::remove_all(dir);
    GTEST_SKIP() << "this file system or user cannot make a file immutable (chattr +i)";
  }
  std::string message;
  try {
    WriteFilesTogether({{a, "new a"}, {b, "new b"}, {last, "new summary"}}, {stale});
  } catch (const std::runtime_error& error) {
    message = error.what();
  }
  SetImmutable(last, false);
  EXPECT_EQ(message, last + ": cannot replace it (Operation not permitted)");
  EXPECT_EQ(ReadAll(a), "old a");
  EXPECT_EQ(ReadAll(b), "old b");
  EXPECT_EQ(ReadAll(last), "old summary");
  EXPECT_EQ(ReadAll(stale), "old mat");
  EXPECT_EQ(Entries(dir), (std::vector<std::string>{"a.csv", "b.csv", "run.mat", "summary.json"}));
  fs::remove_all(dir);
}

TEST(FilesTest, AnOutputDirectoryIsHeldByOneRunAtATime) {
  const fs::path dir = ScratchDir("lock");
  const std::string out = (dir / "new" / "run").string();
  {
    const DirectoryLock lock(out);
    EXPECT_TRUE(fs::is_directory(out));
    try {
      const DirectoryLock second(out);
      FAIL() << "two holders of one output directory";
    } catch (const std::runtime_error& error) {
      EXPECT_EQ(std::string(error.what()),
                out + ": in use by another run (one run per output directory)");
    }
  }
  // Released empty: the folders it made are gone again.
  EXPECT_EQ(Entries(dir), std::vector<std::string>{});
  {
    const DirectoryLock lock(out);
    WriteFileAtomically(out + "/summary.json", "{}");
  }
  EXPECT_TRUE(fs::exists(out + "/summary.json"));
  { const DirectoryLock again(out); }  // free once released
  fs::remove_all(dir);
}

// A journal is held by one writer at a time; its records reach the file in
// order; Remove leaves no file, and the name is free again at once.
TEST(FilesTest, AJournalIsHeldByOneWriterAndRemovedWhole) {
  const fs::path dir = ScratchDir("journal");
  const std::string path = (dir / "new" / "sweep.journal").string();
  {
    JournalFile journal(path, "in use by another writer");
    EXPECT_EQ(journal.Read(), "");
    journal.Reset("header\n");
    journal.Append("one\n");
    journal.Append("tw");
    EXPECT_EQ(journal.Read(), "header\none\ntw");
    journal.Truncate(11);  // the torn "tw" dropped
    journal.Append("two\n");
    EXPECT_EQ(ReadAll(path), "header\none\ntwo\n");
    try {
      JournalFile second(path, "in use by another writer");
      FAIL() << "two writers of one journal";
    } catch (const std::runtime_error& error) {
      EXPECT_EQ(std::string(error.what()), path + ": in use by another writer");
    }
    journal.Remove();
    EXPECT_FALSE(fs::exists(path));
    JournalFile next(path, "in use by another writer");  // not held by the removed one
    EXPECT_EQ(next.Read(), "");
  }
  { JournalFile again(path, "in use"); }  // free once released
  fs::create_symlink(dir / "elsewhere", dir / "link.journal");
  EXPECT_THROW(JournalFile((dir / "link.journal").string(), "in use"), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir / "elsewhere")) << "written through a symbolic link";
  fs::remove_all(dir);
}

// A killed writer's temporaries ("PATH.tmp.PID.XXXXXX" of a process that no
// longer runs) go with the next write of PATH; a running one's stay.
TEST(FilesTest, TemporariesOfAKilledWriterAreRemovedByTheNext) {
  const fs::path dir = ScratchDir("stale");
  const fs::path table = dir / "table.csv";
  // PID 2^31 - 1 is beyond Linux's pid_max (at most 2^22): no such process.
  WriteFileAtomically((dir / "table.csv.tmp.2147483647.AbC123").string(), std::string(1000, 'x'));
  const std::string live = "table.csv.tmp." + std::to_string(getppid()) + ".XyZ789";
  WriteFileAtomically((dir / live).string(), "in use");
  WriteFileAtomically((dir / "table.csv.tmp.notapid").string(), "not ours");
  WriteFileAtomically(table.string(), "a,b\n");
  EXPECT_EQ(Entries(dir), (std::vector<std::string>{"table.csv", live, "table.csv.tmp.notapid"}));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ipmc::testing
