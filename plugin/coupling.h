// Per-(model, data) coupling context and the registry the MuJoCo callbacks
// dispatch through. The callbacks are process-wide; the state is not.
#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <optional>

#include "plugin/actuators/ipmc_actuators.h"
#include "plugin/fluid/rft_drag.h"

namespace ipmc {

struct CouplingContext {
  const mjModel* model = nullptr;
  std::optional<RftDrag> drag;
  std::unique_ptr<IpmcActuators> actuators;
};

// Attach (ipmc_swim.h) with settings imposed over the model's fields.
bool AttachWithOverrides(const mjModel* m, mjData* d, const IpmcActuatorsOverrides& overrides);

// The context attached to d, or nullptr. The pointer stays valid until d
// is detached or re-attached.
const CouplingContext* FindCoupling(const mjData* d);
// The same, for the thread that steps d (the actuators' state changes).
CouplingContext* FindMutableCoupling(const mjData* d);

}  // namespace ipmc
