// ipmc-swim: resistive-force-theory drag and IPMC actuators for MuJoCo 2.2.
//
// A model declares what it needs in <custom> fields (ipmc_rft_* for the
// drag, ipmc_link* for the actuators; see the README). A program loads
// the model, makes its mjData, and calls Attach once per mjData before
// stepping; mj_step then applies the drag (mjcb_passive) and advances the
// actuators (mjcb_control). Attach/Detach may be called for many
// (model, data) pairs; stepping different pairs from different threads is
// safe. Call Attach before starting threads that step.
#pragma once

#include <mujoco/mujoco.h>

namespace ipmc {

// Reads the model's ipmc_* fields and couples them to d. Returns false
// (and does nothing) for a model without ipmc_* fields. Throws
// std::invalid_argument with a one-line message naming the field and its
// allowed range if a field is malformed. Attaching an attached d again
// replaces its coupling.
bool Attach(const mjModel* m, mjData* d);

// Removes the coupling of d (before mj_deleteData). Returns false if d was
// not attached.
bool Detach(const mjData* d);

// Library version, "MAJOR.MINOR.PATCH".
const char* Version();

}  // namespace ipmc
