// Models for the plugin's unit tests, loaded by MuJoCo alone: MJCF text
// through MuJoCo's virtual file system, or a file of the source tree, with
// the userdata the coupling keeps its state in reserved (ipmc_swim.h,
// "State"), as a program that attaches them does.
#pragma once

#include <mujoco/mujoco.h>

#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include "ipmc_swim/ipmc_swim.h"

namespace ipmc::plugin_test {

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

// The model of MJCF `xml`, with UserdataSize(m) userdata values for a model
// with ipmc_* fields (none for malformed fields: Attach reports them).
// Throws std::runtime_error with MuJoCo's message.
inline ModelPtr LoadXml(const std::string& xml) {
  const auto vfs = std::make_unique<mjVFS>();  // megabytes: not on the stack
  mj_defaultVFS(vfs.get());
  const char* name = "plugin_test_model.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0) {
    mj_deleteVFS(vfs.get());
    throw std::runtime_error("inline model: too large for MuJoCo's virtual file");
  }
  std::memcpy(vfs->filedata[0], xml.data(), xml.size());
  char error[1024] = "";
  mjModel* m = mj_loadXML(name, vfs.get(), error, sizeof(error));
  mj_deleteVFS(vfs.get());
  if (!m) throw std::runtime_error(std::string("inline model: ") + error);
  ModelPtr model(m);
  int needed = 0;
  try {
    needed = UserdataSize(m);
  } catch (const std::invalid_argument&) {
    // Malformed ipmc_* fields: the test's Attach meets them.
  }
  if (model->nuserdata < needed) model->nuserdata += needed;
  return model;
}

// The text of `path`, relative to the source tree (IPMC_SWIM_SOURCE_DIR,
// tests/test_paths.h).
inline std::string SourceFileText(const std::string& path) {
  std::ifstream in(std::string(IPMC_SWIM_SOURCE_DIR) + "/" + path);
  if (!in) throw std::runtime_error(path + ": cannot open it");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace ipmc::plugin_test
