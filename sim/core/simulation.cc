#include "sim/core/simulation.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <utility>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "ipmc_swim/ipmc_swim.h"
#include "sim/io/files.h"

namespace ipmc {
namespace {

// MuJoCo's load error on one line: "XML parse error 13:\nError=..." keeps
// its reason.
std::string LoadError(const char* text) {
  std::string line;
  std::istringstream lines(text);
  for (std::string part; std::getline(lines, part);) {
    while (!part.empty() && (part.back() == ' ' || part.back() == '\r')) part.pop_back();
    if (part.empty()) continue;
    if (!line.empty()) line += line.back() == ':' ? " " : "; ";
    line += part;
  }
  return line.empty() ? "MuJoCo could not load it (no reason given)" : line;
}

// Reserves the userdata the coupling of m keeps its state in (after any
// the model declares for the program), so that every mjData made from m
// can be attached. A malformed ipmc_* field is left for Attach to report,
// naming the file.
void ReserveCouplingUserdata(mjModel* m) {
  int needed = 0;
  try {
    needed = UserdataSize(m);
  } catch (const std::invalid_argument&) {
    return;
  }
  if (m->nuserdata < needed) m->nuserdata += needed;
}

}  // namespace

ModelPtr LoadModelFile(const std::string& path) {
  std::error_code status;
  if (std::filesystem::is_directory(path, status)) {
    throw std::runtime_error(path + ": is a directory, not a model file (MJCF)");
  }
  RequireRegularInput(path, "model file (MJCF)");
  if (!std::ifstream(path).good()) {
    throw std::runtime_error(path + ": cannot open model file (" + std::strerror(errno) + ")");
  }
  if (std::filesystem::file_size(path, status) == 0 && !status) {
    throw std::runtime_error(path + ": empty model file (MJCF expected)");
  }
  char error[1024] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
  if (!m) throw std::runtime_error(path + ": " + LoadError(error));
  ReserveCouplingUserdata(m);
  return ModelPtr(m);
}

ModelPtr LoadModelString(const std::string& xml, const std::string& directory) {
  // MuJoCo reads the text from a virtual file (mjVFS) named as if it were
  // in `directory`, where it looks for the files the text names.
  struct VfsDeleter {
    void operator()(mjVFS* vfs) const {
      mj_deleteVFS(vfs);
      delete vfs;
    }
  };
  std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);
  mj_defaultVFS(vfs.get());
  if (xml.size() > static_cast<size_t>(std::numeric_limits<int>::max()) ||
      mj_makeEmptyFileVFS(vfs.get(), "ipmc_swim_model.xml", static_cast<int>(xml.size())) != 0) {
    throw std::runtime_error("inline model: too large for MuJoCo's virtual file (" +
                             std::to_string(xml.size()) + " bytes)");
  }
  std::memcpy(vfs->filedata[0], xml.data(), xml.size());
  const std::string name =
      directory.empty() ? "ipmc_swim_model.xml"
                        : (std::filesystem::path(directory) / "ipmc_swim_model.xml").string();
  char error[1024] = "";
  mjModel* m = mj_loadXML(name.c_str(), vfs.get(), error, sizeof(error));
  if (!m) throw std::runtime_error(std::string("inline model: ") + LoadError(error));
  ReserveCouplingUserdata(m);
  return ModelPtr(m);
}

Simulation::Simulation(ModelPtr m, const std::string& source)
    : model_(std::move(m)), source_(source) {
  ReserveCouplingUserdata(model_.get());
  data_.reset(mj_makeData(model_.get()));
  try {
    Attach(model_.get(), data_.get());
  } catch (const std::exception& e) {
    throw std::runtime_error(source_ + ": " + e.what());
  }
  mj_forward(model_.get(), data_.get());
}

Simulation::~Simulation() { Detach(data_.get()); }

void Simulation::Step(bool compute_sensors) {
  StepSettings options;
  options.compute_sensors = compute_sensors;
  if (!ipmc::Step(model_.get(), data_.get(), options)) {
    // ipmc::Step's error names the step's time.
    throw std::runtime_error(source_ + ": " + LastError(data_.get()));
  }
}

int RequireId(const mjModel* m, mjtObj type, const std::string& name, const std::string& source) {
  const int id = mj_name2id(m, type, name.c_str());
  if (id < 0) throw std::runtime_error(source + ": model has no " + name);
  return id;
}

}  // namespace ipmc
