// ipmc-swim: resistive-force-theory drag and IPMC actuators for MuJoCo 2.2.
//
// A model declares what it needs in <custom> fields (ipmc_rft_* for the
// drag, ipmc_link* for the actuators; see docs/LIBRARY.md). A program loads
// the model, makes its mjData, and calls Attach once per mjData before
// stepping; mj_step then applies the drag (mjcb_passive) and advances the
// IPMC link models to d->time, writing their active moments into the
// ipmc_* motors' ctrl (mjcb_control). Attach/Detach may be called for many
// (model, data) pairs; stepping different pairs from different threads is
// safe. Call Attach before starting threads that step.
//
// State. The drag has none. The IPMC actuators' state lives in the
// coupling, outside mjData: the link models' integrated state x and its
// time t_x, the held voltages, each link's last curvature (where the next
// step's root-finding starts) and the count of clamped deflections. Each
// step advances x from t_x to d->time. MuJoCo's own functions do not see
// this state:
//  - mj_resetData, mj_resetDataKeyframe, or assigning an earlier d->time:
//    the next step (or SetVoltages) finds d->time < t_x. Call ResetState
//    (start from rest) or RestoreState (go back to a saved state) after
//    rewinding. Without either, the coupling does what ResetState does and
//    reports the rewind through mju_warning: a rewind the program did not
//    declare may be a copy of an older mjData whose actuator state is lost.
//  - mj_copyData(dst, m, src): dst has no coupling until attached, and an
//    attached dst keeps its own coupling state. To continue src in dst:
//    Attach(m, dst), mj_copyData(dst, m, src), RestoreState(dst,
//    SaveState(src)).
//  - mj_deleteData: Detach first.
// Attach (also on an attached d) gives the state of ResetState at
// d->time.
//
// Dynamics. A model with the text field ipmc_dynamics = stokes (or a
// program's override) is stepped without inertia, its velocity taken from
// the balance of drag, hinge and active forces at every step; call Step
// instead of mj_step to get it (docs/DYNAMICS.md): for such a model the
// drag callback adds nothing (the Stokes step solves for the drag), so
// mj_step would step it without drag. Step also runs mj_step for an
// inertial model and reports the callbacks' failures.
//
// Callbacks. The coupling installs mjcb_passive (drag) and mjcb_control
// (actuators) at the first Attach and chains to the callbacks that were
// set before. A host that sets mjcb_passive or mjcb_control after Attach
// replaces them: the drag or the actuators are silently off under mj_step;
// Step notices a callback that did not run and warns once through
// mju_warning. No C++ exception crosses a callback: a failure inside one
// (for example the actuators' ODE solver giving up) is recorded for d,
// reported through mju_warning, and returned by LastError; Step returns
// false after such a step.
//
// Warnings (a clamped free deflection, an undeclared rewind) go through
// mju_warning: MuJoCo prints them to stdout and appends them to
// MUJOCO_LOG.TXT unless the program sets mju_user_warning. Each names the
// link or the times; mju_user_warning is called from the thread that steps.
#pragma once

#include <mujoco/mujoco.h>

#include <vector>

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
// std::invalid_argument on a wrong count, a non-finite voltage, one
// beyond the model's limit (ipmc_voltage_limit_V, 100 V by default) or a
// non-finite d->time.
int SetVoltages(const mjData* d, const double* voltage_V, int count);

// Everything the coupling's next step depends on besides mjData. Empty
// vectors and zeros for a coupling without IPMC actuators.
struct CouplingState {
  double time_s = 0;                  // t_x: the time of actuator_state [s]
  std::vector<double> actuator_state; // x: the links' stacked model states [mm, V]
  std::vector<double> voltage_V;      // held voltage of each link [V]
  std::vector<double> curvature_1_m;  // each link's last curvature [1/m]
  long clamp_count = 0;               // clamped deflections so far (only the first warns)
};

// The coupling state of d. Also makes d's link models restart their
// integration at time_s, as a voltage change does, so that d and every
// mjData restored from the result step bit-identically; d's own later
// values change within the integration tolerance (ipmc_cvode_rel_tol; not
// at all with the default ipmc_actuator_integration = exact).
// Call from the thread that steps d. Throws std::invalid_argument if d is
// not attached.
CouplingState SaveState(const mjData* d);

// Sets the coupling of d to `state`, saved from a coupling of the same
// model, after the mjData saved with it was copied into d (time_s <=
// d->time). Throws std::invalid_argument with a one-line message naming
// the field if d is not attached, a vector has the wrong size, a value is
// not finite, a voltage is beyond the limit SetVoltages enforces,
// clamp_count < 0 or time_s > d->time; d is unchanged then.
void RestoreState(const mjData* d, const CouplingState& state);

// The state Attach gives, at d->time: the link models at rest, 0 V on
// every link, no clamps counted. Call after mj_resetData. Throws
// std::invalid_argument if d is not attached.
void ResetState(const mjData* d);

// One time step of d: the Stokes-flow step for a model attached with
// ipmc_dynamics = stokes, mj_step otherwise (also for a d not attached).
// Returns false if d->time is not finite, a callback failed during the
// step, the Stokes force balance was singular, or the step diverged;
// LastError(d) says why (the state may be partly advanced: stop or
// restore). A divergence is: MuJoCo's bad-state checks in mj_step firing
// (a position, velocity or acceleration not finite or beyond mjMAXVAL,
// after which MuJoCo has reset d; a bad control, which it zeroed), or a
// position, velocity or IPMC link deflection bad after the step. Its
// LastError begins with kDivergedPrefix and names the step's start time
// and the degree of freedom, joint or link; that of any other failure
// during the step begins with "step at t = T s failed: ".
bool Step(const mjModel* m, mjData* d);
constexpr char kDivergedPrefix[] = "simulation diverged at t = ";

// The failure of d's last Step (or of a callback run since, e.g. by
// mj_forward), one line; "" if none or d is not attached. Valid until the
// next Step of d.
const char* LastError(const mjData* d);

// Library version, "MAJOR.MINOR.PATCH".
const char* Version();

}  // namespace ipmc
