#include "sim/core/simulation.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "ipmc_swim/ipmc_swim.h"
#include "plugin/coupling.h"

namespace ipmc {
namespace {

std::string FirstLine(const char* text) {
  std::string line(text);
  const size_t end = line.find('\n');
  return end == std::string::npos ? line : line.substr(0, end);
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
  if (!std::ifstream(path).good()) {
    throw std::runtime_error(path + ": cannot open model file");
  }
  char error[1024] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
  if (!m) throw std::runtime_error(path + ": " + FirstLine(error));
  return ModelPtr(m);
}

ModelPtr LoadModelString(const std::string& xml) {
  char name[] = "/tmp/ipmc_swim_model_XXXXXX.xml";
  const int fd = mkstemps(name, 4);
  if (fd < 0) throw std::runtime_error("cannot create a temporary model file");
  close(fd);
  {
    std::ofstream out(name);
    out << xml;
  }
  char error[1024] = "";
  mjModel* m = mj_loadXML(name, nullptr, error, sizeof(error));
  std::remove(name);
  if (!m) throw std::runtime_error(std::string("inline model: ") + FirstLine(error));
  return ModelPtr(m);
}

Simulation::Simulation(ModelPtr m, const std::string& source,
                       const IpmcActuatorsOverrides& overrides)
    : model_(std::move(m)), data_(mj_makeData(model_.get())), source_(source) {
  try {
    AttachWithOverrides(model_.get(), data_.get(), overrides);
  } catch (const std::exception& e) {
    throw std::runtime_error(source_ + ": " + e.what());
  }
  mj_forward(model_.get(), data_.get());
}

Simulation::~Simulation() { Detach(data_.get()); }

void Simulation::Step(bool compute_sensors) {
  mjModel* m = model_.get();
  if (compute_sensors) {
    mj_step(m, data_.get());
  } else {
    const int flags = m->opt.disableflags;
    m->opt.disableflags = flags | mjDSBL_SENSOR;
    mj_step(m, data_.get());
    m->opt.disableflags = flags;
  }
  const mjData* d = data_.get();
  bool finite = true;
  for (int i = 0; i < model_->nq && finite; ++i) finite = std::isfinite(d->qpos[i]);
  for (int i = 0; i < model_->nv && finite; ++i) finite = std::isfinite(d->qvel[i]);
  if (!finite || d->warning[mjWARN_BADQACC].number > 0) {
    std::ostringstream msg;
    msg << source_ << ": simulation diverged at t = " << d->time
        << " s (reduce option timestep, now " << model_->opt.timestep << " s)";
    throw std::runtime_error(msg.str());
  }
}

int RequireId(const mjModel* m, mjtObj type, const std::string& name, const std::string& source) {
  const int id = mj_name2id(m, type, name.c_str());
  if (id < 0) throw std::runtime_error(source + ": model has no " + name);
  return id;
}

}  // namespace ipmc
