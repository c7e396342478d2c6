#include "sim/core/data_paths.h"

#include "ipmc_swim/ipmc_swim.h"

#include <filesystem>
#include <system_error>

namespace ipmc {
namespace {

// <prefix>/share/ipmc_swim/<folder> when the running program is
// <prefix>/bin/ipmc-swim (or links this library from <prefix>/lib), else
// the source tree's folder.
std::string ShippedDir(const char* folder, const char* source_tree_dir) {
  std::error_code error;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) {
    const std::filesystem::path installed = exe.parent_path().parent_path() / "share" / "ipmc_swim" / folder;
    if (std::filesystem::is_directory(installed, error)) return installed.string();
  }
  return source_tree_dir;
}

}  // namespace

std::string ModelsDir() { return ShippedDir("models", IPMC_SWIM_MODELS_DIR); }
std::string ScenariosDir() { return ShippedDir("scenarios", IPMC_SWIM_SCENARIOS_DIR); }
const char* ProgramVersion() { return Version(); }

}  // namespace ipmc
