// Per-(model, data) coupling context and the registry the MuJoCo callbacks
// dispatch through. The callbacks are process-wide; the state is not.
#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <optional>
#include <string>

#include "plugin/actuators/ipmc_actuators.h"
#include "plugin/fluid/fluid_model.h"
#include "plugin/fluid/rft_drag.h"
#include "plugin/dynamics/step_model.h"
#include "plugin/dynamics/stokes_step.h"

namespace ipmc {

struct CouplingContext {
  const mjModel* model = nullptr;
  // The segments the fluid acts on and their RFT coefficients (the model's
  // ipmc_rft_* fields), absent without a viscosity.
  std::optional<RftDrag> drag;
  // The fluid model over drag's segments (MakeFluid), with drag.
  std::unique_ptr<Fluid> fluid;
  // The settings the drag was made with over the model's fields
  // (SetFluidField rebuilds it with them).
  RftDragOverrides fluid_overrides;
  // Scratch data of the step model for FluidForces (made at first use).
  std::unique_ptr<mjData, void (*)(mjData*)> scratch{nullptr, mj_deleteData};
  std::unique_ptr<IpmcActuators> actuators;
  Dynamics dynamics = Dynamics::kInertial;
  std::unique_ptr<StokesStepper> stokes;  // with Dynamics::kStokes
  // The model Step steps d with (MakeStepModel): model with the
  // integrator and hinge damping the coupling chose; the callbacks act
  // for either.
  StepModel step;
  // Whether the callbacks act for a step of m.
  bool Serves(const mjModel* m) const { return m == model || m == step.model.get(); }
  // The state's block in d->userdata (ipmc_swim.h, "State"): its last
  // state_size values, from state_offset: the actuators' state, the Stokes
  // stepper's history, and a header saying whose state it is (owner, the
  // count of its writes, state_size, a tag).
  int state_offset = 0, state_size = 0;
  double owner = 0;   // this coupling's id, unique in the process
  double writes = 0;  // how often it wrote the block
  // The block held another coupling's history (or an older one of this):
  // the next Stokes step takes it first.
  bool load_history = false;
  // The first failure of a callback since the last Step (LastError), and
  // how often each callback ran for d (Step detects a replaced callback).
  std::string error;
  unsigned long passive_calls = 0, control_calls = 0;
  bool warned_replaced_callback = false;
};

// Attach (ipmc_swim.h) with settings imposed over the model's fields.
bool AttachWithOverrides(const mjModel* m, mjData* d, const IpmcActuatorsOverrides& overrides,
                         const RftDragOverrides& fluid = {});

// The userdata values a coupling of m with these settings needs (0 for a
// model without ipmc_* fields); UserdataSize with overrides.
int UserdataSizeWithOverrides(const mjModel* m, const IpmcActuatorsOverrides& overrides,
                              const RftDragOverrides& fluid = {});

// The context attached to d, or nullptr. The pointer stays valid until d
// is detached or re-attached.
const CouplingContext* FindCoupling(const mjData* d);
// The same, for the thread that steps d (the actuators' state changes).
CouplingContext* FindMutableCoupling(const mjData* d);

}  // namespace ipmc
