#include "sim/core/simulation.h"

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <utility>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "ipmc_swim/ipmc_swim.h"
#include "plugin/coupling.h"
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
void ReserveCouplingUserdata(mjModel* m, const IpmcActuatorsOverrides& overrides = {},
                             const RftDragOverrides& fluid = {}) {
  int needed = 0;
  try {
    needed = UserdataSizeWithOverrides(m, overrides, fluid);
  } catch (const std::invalid_argument&) {
    return;
  }
  if (m->nuserdata < needed) m->nuserdata += needed;
}

}  // namespace

bool UseEulerWhereImplicitAddsNothing(mjModel* m) {
  if (m->opt.integrator != mjINT_IMPLICIT) return false;
  if (m->opt.density > 0 || m->opt.viscosity > 0) return false;
  for (int t = 0; t < m->ntendon; ++t) {
    if (m->tendon_damping[t] != 0) return false;
  }
  for (int a = 0; a < m->nu; ++a) {
    // gain = gainprm[0] + gainprm[1] length + gainprm[2] velocity (affine),
    // bias = biasprm[0] + biasprm[1] length + biasprm[2] velocity.
    const bool gain_velocity =
        m->actuator_gaintype[a] == mjGAIN_AFFINE && m->actuator_gainprm[mjNGAIN * a + 2] != 0;
    const bool bias_velocity =
        m->actuator_biastype[a] == mjBIAS_AFFINE && m->actuator_biasprm[mjNBIAS * a + 2] != 0;
    if (gain_velocity || bias_velocity) return false;
  }
  m->opt.integrator = mjINT_EULER;
  return true;
}

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

ModelPtr LoadModelString(const std::string& xml) {
  char name[] = "/tmp/ipmc_swim_model_XXXXXX.xml";
  const int fd = mkstemps(name, 4);
  if (fd < 0) throw std::runtime_error("cannot create a temporary model file");
  // A full disk or a file size limit fails here, naming the reason, not
  // later as an XML error about a torn file.
  size_t written = 0;
  while (written < xml.size()) {
    const ssize_t n = write(fd, xml.data() + written, xml.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    written += static_cast<size_t>(n);
  }
  const int write_errno = errno;
  close(fd);
  if (written < xml.size()) {
    std::remove(name);
    throw std::runtime_error(std::string("cannot write the temporary model file ") + name +
                             " (" + std::strerror(write_errno) + ")");
  }
  char error[1024] = "";
  mjModel* m = mj_loadXML(name, nullptr, error, sizeof(error));
  std::remove(name);
  if (!m) throw std::runtime_error(std::string("inline model: ") + LoadError(error));
  ReserveCouplingUserdata(m);
  return ModelPtr(m);
}

Simulation::Simulation(ModelPtr m, const std::string& source,
                       const IpmcActuatorsOverrides& overrides, const RftDragOverrides& fluid)
    : model_(std::move(m)), source_(source) {
  ReserveCouplingUserdata(model_.get(), overrides, fluid);
  data_.reset(mj_makeData(model_.get()));
  try {
    AttachWithOverrides(model_.get(), data_.get(), overrides, fluid);
  } catch (const std::exception& e) {
    throw std::runtime_error(source_ + ": " + e.what());
  }
  mj_forward(model_.get(), data_.get());
}

Simulation::~Simulation() { Detach(data_.get()); }

void Simulation::Step(bool compute_sensors) {
  mjModel* m = model_.get();
  const int flags = m->opt.disableflags;
  if (!compute_sensors) m->opt.disableflags = flags | mjDSBL_SENSOR;
  const bool stepped = ipmc::Step(m, data_.get());
  m->opt.disableflags = flags;
  if (!stepped) {
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
