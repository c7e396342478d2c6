// Owns one mjModel/mjData pair with the ipmc_swim coupling attached.
#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <string>

#include "plugin/actuators/ipmc_actuators.h"
#include "plugin/fluid/rft_drag.h"

namespace ipmc {

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

// Loads an MJCF file. Throws std::runtime_error "PATH: reason" if the
// file is missing or MuJoCo rejects it.
ModelPtr LoadModelFile(const std::string& path);
// Loads MJCF text (written to a private temporary file for MuJoCo's parser).
ModelPtr LoadModelString(const std::string& xml);

// Switches m from MuJoCo's implicit integrator to its Euler integrator
// where the two treat the same forces implicitly: MuJoCo 2.2's implicit
// step differs from Euler only in the velocity derivatives of the
// actuator forces (velocity gains and biases), of tendon damping and of
// its own fluid model, while Euler too integrates the joints' damping
// implicitly; the callback forces are explicit in both. So with none of
// those three in the model Euler gives the same stability at 0.4 of the
// cost of a step (docs/RUNS.md, "Time step and integrator"). The closed-loop and
// bench runs call it; a gait's servos have velocity gains and keep
// implicit. Returns true if it switched.
bool UseEulerWhereImplicitAddsNothing(mjModel* m);

class Simulation {
 public:
  // Takes ownership of m, makes its data and attaches the coupling, with
  // `overrides` and `fluid` imposed over the model's fields. Errors from
  // the model's ipmc_* fields are prefixed with `source` (the file).
  Simulation(ModelPtr m, const std::string& source,
             const IpmcActuatorsOverrides& overrides = {}, const RftDragOverrides& fluid = {});
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  mjModel* model() { return model_.get(); }
  const mjModel* model() const { return model_.get(); }
  mjData* data() { return data_.get(); }
  const mjData* data() const { return data_.get(); }
  const std::string& source() const { return source_; }

  // One step (ipmc::Step: mj_step, or the Stokes-flow step for a model
  // with ipmc_dynamics = stokes or the override); throws
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
