// The output-file helper: complete files with the mode a new file gets
// under the umask, or no file and the reason.
#include <gtest/gtest.h>

#include <sys/stat.h>

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

}  // namespace
}  // namespace ipmc::testing
