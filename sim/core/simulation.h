// Owns one mjModel/mjData pair with the ipmc_swim coupling attached.
#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <string>

#include "ipmc_swim/ipmc_swim.h"

namespace ipmc {

// Loads an MJCF file. Throws std::runtime_error "PATH: reason" if the
// file is missing or MuJoCo rejects it.
ModelPtr LoadModelFile(const std::string& path);
// Loads MJCF text; the files it names (includes, meshes) are looked up in
// `directory` (the working directory if empty). Throws std::runtime_error
// "inline model: reason".
ModelPtr LoadModelString(const std::string& xml, const std::string& directory = "");

class Simulation {
 public:
  // Takes ownership of m, makes its data and attaches the coupling
  // (ipmc::Attach: a scenario's settings are written into the model's
  // fields, sim/core/scenario_simulation.h). Errors from the model's ipmc_*
  // fields are prefixed with `source` (the file).
  Simulation(ModelPtr m, const std::string& source);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  mjModel* model() { return model_.get(); }
  const mjModel* model() const { return model_.get(); }
  mjData* data() { return data_.get(); }
  const mjData* data() const { return data_.get(); }
  const std::string& source() const { return source_; }

  // One step (ipmc::Step: the coupling's step of the model, or the
  // Stokes-flow step for a model with ipmc_dynamics = stokes or the
  // override); throws
  // std::runtime_error "SOURCE: " and ipmc::LastError's line if the step
  // failed: a divergence (MuJoCo reported a bad state and reset it, or a
  // position, velocity or link deflection stopped being finite) names its
  // time and degree of freedom; any other failure is prefixed with the
  // step's time. With compute_sensors = false
  // MuJoCo skips its sensor stages in this step and sensordata keeps the
  // values of the last step that computed them, for a caller that reads the
  // sensors only every few steps (MuJoCo fills sensordata during the step,
  // from the state at its start).
  void Step(bool compute_sensors = true);

 private:
  ModelPtr model_;
  DataPtr data_;
  std::string source_;
};

// Index helpers that throw std::runtime_error naming the missing object.
int RequireId(const mjModel* m, mjtObj type, const std::string& name, const std::string& source);

}  // namespace ipmc
