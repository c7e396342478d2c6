// ipmc-swim: resistive-force-theory drag and IPMC actuators for MuJoCo 2.2.
//
// A model declares what it needs in <custom> fields (ipmc_rft_* for the
// drag, ipmc_link* for the actuators; see the README). A program loads
// the model, makes its mjData, and calls Attach once per mjData before
// stepping; mj_step then applies the drag (mjcb_passive) and advances the
// IPMC link models to d->time, writing their active moments into the
// ipmc_* motors' ctrl (mjcb_control). Attach/Detach may be called for many
// (model, data) pairs; stepping different pairs from different threads is
// safe. Call Attach before starting threads that step.
//
// Warnings (a clamped free deflection) go through mju_warning: MuJoCo
// prints them to stdout and appends them to MUJOCO_LOG.TXT unless the
// program sets mju_user_warning. Each names the link and the time;
// mju_user_warning is called from the thread that steps.
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

// Sets the IPMC links' voltages [V] from d->time on (held until changed).
// `count` must equal the number of links in the model's ipmc_links field.
// Returns that number, or 0 if d has no IPMC actuators. Throws
// std::invalid_argument on a wrong count or a non-finite voltage.
int SetVoltages(const mjData* d, const double* voltage_V, int count);

// Library version, "MAJOR.MINOR.PATCH".
const char* Version();

}  // namespace ipmc
