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
// State. The coupling's state lives in mjData, in the last UserdataSize(m)
// values of d->userdata (the model reserves them: <size nuserdata="N"/>
// in the MJCF, or m->nuserdata = ipmc::UserdataSize(m) before mj_makeData;
// Attach refuses a model with fewer and names N): the IPMC link models'
// integrated state x and its time t_x, the held voltages, each link's last
// curvature (where the next step's root-finding starts), the count of
// clamped deflections, the Stokes stepper's last step (its start and end
// positions) and a header saying whose state it is. So MuJoCo's own
// functions act on it as on the rest of mjData:
//  - mj_copyData(dst, m, src): dst holds src's state. Attach(m, dst) (or
//    a dst attached before the copy) continues it: dst steps bit for bit
//    as src does, in either dynamics, with the rft fluid model (and any
//    whose resistance is a function of the position alone); the dense
//    fluids' resistance cache (stokeslets, ribbon, plates: exact
//    evaluations and the fit in time between them) is the coupling's own,
//    so a copy follows within the fit's tolerance; with
//    ipmc_actuator_integration = cvode, within its tolerance. Step refuses a dst that holds a coupling's state and is
//    not attached (mj_step would step it without drag or actuators).
//  - mj_resetData, mj_resetDataKeyframe: they zero userdata; the next
//    step starts the link models from rest (0 V) at d->time.
//  - assigning an earlier d->time without the state that belongs to it:
//    the link models cannot go back, so they restart from rest at d->time
//    and the coupling reports it through mju_warning.
// SaveState and RestoreState copy the actuators' part out and back in
// (for a program that keeps states outside mjData); ResetState sets rest.
// Attach takes the state d holds (a copy of an attached mjData, or d's
// own under an earlier Attach), or rest for a d whose block is zero.
//
// Stepping. Step steps d with the coupling's own copy of m, taken afresh
// from m before every step (so a change to m between steps, e.g. an
// actuator's gain or the timestep, takes effect as under mj_step), in
// which the coupling makes the numerical choices the ipmc-swim program makes (docs/LIBRARY.md, "How Step steps"): in
// inertial dynamics each spring hinge's damping c becomes
// c_eff = k h / (1 - exp(-k h / c)) for MuJoCo's Euler or implicit step
// (the exact relaxation of a massless hinge over a step; stable for every
// h), flexible links' active moments follow a first-order hold over the
// step, and MuJoCo's Euler integrator replaces the implicit one where the
// two treat the same forces implicitly. A model file, Attach,
// SetVoltages and Step so give what `ipmc-swim run` gives (a run writes
// the model it stepped as model.xml). The ipmc_* fields are read at Attach:
// change them with SetFluidField, or Attach again.
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

#include <memory>
#include <vector>

namespace ipmc {

// Owners of a model and its data: mj_deleteModel and mj_deleteData when
// they go (Detach d first if it is attached).
struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

// Reads the model's ipmc_* fields and couples them to d. Returns false
// (and does nothing) for a model without ipmc_* fields. Throws
// std::invalid_argument with a one-line message naming the field and its
// allowed range if a field is malformed. Attaching an attached d again
// replaces its coupling.
bool Attach(const mjModel* m, mjData* d);

// The number of d->userdata values the coupling of m keeps its state in
// (the last ones), 0 for a model without ipmc_* fields. Throws as Attach
// does for malformed fields.
int UserdataSize(const mjModel* m);

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

// The state of a d never attached, at d->time: the link models at rest,
// 0 V on every link, no clamps counted (what mj_resetData gives). Throws
// std::invalid_argument if d is not attached.
void ResetState(const mjData* d);

// One time step of d: the Stokes-flow step for a model attached with
// ipmc_dynamics = stokes, mj_step otherwise (also for a d not attached of
// a model without ipmc_* fields). Returns false if d is not attached (or
// attached with another model) but m has ipmc_* fields or d holds a
// coupling's state, if d's userdata block holds something else, if
// d->time is not finite, a callback failed during the
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

// What a step computes besides the state.
struct StepSettings {
  // false: MuJoCo skips its sensor stages in this step and d->sensordata
  // keeps the values of the last step that computed them (for a program
  // that reads the sensors only every few steps; MuJoCo fills sensordata
  // during the step, from the state at its start). The state is the same.
  bool compute_sensors = true;
};
// Step with options.
bool Step(const mjModel* m, mjData* d, const StepSettings& options);

// The failure of d's last Step (or of a callback run since, e.g. by
// mj_forward), one line; "" if none. For a d not attached, the failure of
// its last Step in this thread. Valid until the next Step of d.
const char* LastError(const mjData* d);

// Whether d is attached (Attach returned true for it and no Detach since).
bool IsAttached(const mjData* d);

// ---- Facts and forces of an attached d. Each throws std::invalid_argument
// (one line) if d is not attached or an index is out of range.

// The number of IPMC links (the model's ipmc_links), 0 without actuators.
int LinkCount(const mjData* d);
// The joints (ids) of link `link` (0-based), its root hinge first, then
// the hinges of its sub-segments (ipmc_segments_per_link).
std::vector<int> LinkJoints(const mjData* d, int link);
// The voltage link `link` holds [V] (SetVoltages).
double LinkVoltage_V(const mjData* d, int link);
// The active moment the link's model applies at each of its joints
// (LinkJoints' order) [N m], as the last step applied it (d->ctrl of the
// ipmc_<joint> motors).
std::vector<double> LinkActiveMoments_N_m(const mjData* d, int link);
// The lengths [m] of link `link`'s sub-segments, in LinkJoints' order.
std::vector<double> LinkSegmentLengths_m(const mjData* d, int link);
// The link's length [m], its sub-segments' summed.
double LinkLength_m(const mjData* d, int link);
// The free tip deflection [mm] the link's model gives at its state's
// time: the output of its transfer function (the plant below), before the
// link's chain turns it into joint angles (docs/MODEL.md).
double LinkFreeDeflection_mm(const mjData* d, int link);
// How often a link's free deflection lay beyond its chain's reach and was
// clamped to it (only the first clamp warns).
long ClampCount(const mjData* d);

// One Oustaloup approximation of s^order over [low, high] rad/s with
// `pairs` zero/pole pairs (or N of the 2N + 1 variant).
struct OustaloupBand {
  double order = 0, low_rad_s = 0, high_rad_s = 0;
  int pairs = 0;
  bool two_n_plus_one = false;
};
// A link's plant, voltage [V] to free tip deflection [mm], as Attach made
// it from the model's fields (ipmc_model, ipmc_plants, the per-link
// ipmc_a0_mm_per_V / ipmc_b1 / ipmc_b2_s2 / ipmc_alpha, scaled to the
// link's length; docs/MODEL.md):
//   P(s) = s^integrator.order G(s),
//   G1(s) = a0 / (b2 s^2 + b1 s + 1),  G2(s) = a0 / (b1 s^alpha + 1),
// each fractional power realised by its Oustaloup band.
struct LinkPlantParameters {
  bool g2 = false;         // ipmc_model = g2; G1 otherwise
  double a0_mm_per_V = 0;  // static gain of G
  double b1 = 0;           // [s] for G1, [s^alpha] for G2
  double b2_s2 = 0;        // G1 only
  double alpha = 0;        // G2's order
  OustaloupBand integrator, fractional_lag;  // s^-0.5; G2's s^-alpha
};
LinkPlantParameters LinkPlantOf(const mjData* d, int link);

// How the last step applied link `link`'s active moments [N m], per joint
// in LinkJoints' order: with the first-order hold (flexible links in
// inertial dynamics; docs/LIBRARY.md, "How Step steps") the moments ramp
// from start_N_m to end_N_m over the step; otherwise the step held the
// moments LinkActiveMoments_N_m gives and the vectors are empty.
struct MomentHold {
  bool first_order = false;
  std::vector<double> start_N_m, end_N_m;
};
MomentHold LinkMomentHold(const mjData* d, int link);

// Whether Step steps d without inertia (ipmc_dynamics = stokes).
bool StokesDynamics(const mjData* d);
// The damping each dof's step takes [N m s/rad] (nv values): in inertial
// dynamics each spring hinge's c_eff = k h / (1 - exp(-k h / c)) (above),
// else the model's dof_damping.
std::vector<double> StepDamping(const mjModel* m, const mjData* d);
// The power [W] the fluid took in d's last step, as the step took it: in
// Stokes dynamics v^T D v with the velocity it solved for and the
// resistance D at the step's midpoint (docs/ENERGY.md; FluidPower_W
// recomputes it at the step's end), in inertial dynamics the drag's power
// at d's positions and velocities. 0 without drag.
double StepFluidPower_W(const mjModel* m, const mjData* d);

// What the fluid of d's coupling is (its fields, and SetFluidField).
struct FluidFacts {
  bool drag = false;                       // the model declares a fluid
  double viscosity_Pa_s = 0;
  double density_kg_m3 = 0;                // for Reynolds numbers only
  std::vector<double> segment_length_m;    // the segments it acts on
  double strip_width_m = 0;  // ipmc_strip_width_m, else twice ipmc_rft_equivalent_radius_m
  // The drag of the body laid straight and towed along its length, per
  // unit speed [N s/m].
  double towing_drag_N_s_m = 0;
  // A scale of the body's rotational drag about one end [N m s].
  double rotational_drag_N_m_s = 0;
};
FluidFacts FluidOf(const mjData* d);
// How often d's dense fluid (stokeslets, ribbon, plates) evaluated its
// resistance exactly, and how often it took it from its fit in time
// between exact evaluations (ipmc_fluid_<model>_fit_tolerance), since
// Attach; zeros for the other fluids. The rest of its evaluations reused
// the last one (the same shape, or without the fit a shape within its
// tolerance).
struct ResistanceEvaluations {
  long exact = 0;
  long fitted = 0;
};
ResistanceEvaluations FluidResistanceEvaluations(const mjData* d);
// The drag's generalised resistance at d's positions: the nv x nv matrix
// (row-major) C with qfrc = -C qvel that the drag callback applies.
// Empty without drag. A dense fluid's cache may take the evaluation: call
// from the thread that steps d.
std::vector<double> DragMatrix(const mjModel* m, const mjData* d);

// The fluid's force and torque on one body, world frame, SI units, the
// torque about the body's origin (d->xpos).
struct BodyFluidForce {
  int body = -1;
  double force_N[3] = {0, 0, 0};
  double torque_N_m[3] = {0, 0, 0};
};
// The fluid's force and torque on every body it acts on, from d's
// positions and velocities (qpos, qvel: recomputed, so also right after a
// step): the drag the callback applies in inertial dynamics; in Stokes
// dynamics the drag that balances the velocities the step solved for (the
// step takes its resistance at the step's midpoint: the two differ by
// O(h) in a shape that moves). Empty without drag. Uses the coupling's
// scratch data: call from the thread that steps d.
std::vector<BodyFluidForce> FluidForces(const mjModel* m, const mjData* d);
// The power the body loses to the fluid [W], -sum(F . v + T . w) over
// FluidForces (>= 0).
double FluidPower_W(const mjModel* m, const mjData* d);

// Sets a numeric fluid field of d's coupling (ipmc_rft_viscosity_Pa_s, or
// any ipmc_rft_* / ipmc_fluid_* numeric the model declares), as if the
// model file held `value`; the drag is rebuilt from the fields (the Stokes
// step starts afresh). m itself is unchanged. Throws std::invalid_argument
// naming the field and its range (d unchanged then), or if the model does
// not declare it.
void SetFluidField(const mjData* d, const char* field, double value);

// Library version, "MAJOR.MINOR.PATCH".
const char* Version();

}  // namespace ipmc
