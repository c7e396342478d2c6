#include "plugin/coupling.h"

#include <atomic>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <mutex>
#include <shared_mutex>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "ipmc_swim/ipmc_swim.h"
#include "plugin/fluid/dense_resistance_fluid.h"
#include "plugin/mjcf/custom_fields.h"

#include <Eigen/Core>

namespace ipmc {
namespace {

// Registry of contexts keyed by mjData. Written by Attach/Detach, read by
// the callbacks; a shared mutex lets many threads step at once. Every
// write bumps `generation`, which validates the lookups each thread keeps
// (FindMutableCoupling).
struct Registry {
  std::shared_mutex mutex;
  std::unordered_map<const mjData*, std::unique_ptr<CouplingContext>> contexts;
  std::atomic<unsigned long> generation{0};
  std::atomic<unsigned long> couplings{0};  // made so far: each one's owner id
  bool callbacks_installed = false;
  mjfGeneric previous_passive = nullptr;
  mjfGeneric previous_control = nullptr;
};

Registry& GetRegistry() {
  static Registry registry;
  return registry;
}

// No exception leaves a callback (MuJoCo's C code calls them): the first
// failure is kept in the context and reported through mju_warning, and
// Step returns false until the caller has seen it (LastError).
void RecordFailure(CouplingContext* context, const char* what) {
  if (!context->error.empty()) return;
  context->error = what;
  mju_warning((std::string("ipmc_swim: ") + what).c_str());
}

// The state block's header, its last values: owner, writes, size, tag.
// The tag is last, so that d->userdata[m->nuserdata - 1] tells a copy of
// an attached mjData from one never attached.
constexpr int kHeaderSize = 4;
constexpr double kStateTag = 0x1.49b0c3d2e1f4p-700;  // an unlikely value

int ActuatorStateSize(const CouplingContext& context) {
  return context.actuators ? context.actuators->StateSize() : 0;
}

// Writes the context's state into d's block (after every change of it).
void WriteState(CouplingContext* context, const mjData* d) {
  const mjModel* m = context->model;
  int offset = context->state_offset;
  if (context->actuators) context->actuators->StoreState(d, offset);
  offset += ActuatorStateSize(*context);
  // A history taken from another coupling stays in the block until the
  // next Stokes step has loaded it.
  if (context->stokes && !context->load_history) context->stokes->StoreHistory(m, d, offset);
  offset += StokesStepper::HistorySize(m);
  // d->userdata is the program's buffer, not part of const mjData.
  double* header = d->userdata + offset;
  header[0] = context->owner;
  header[1] = ++context->writes;
  header[2] = context->state_size;
  header[3] = kStateTag;
}

// Makes the context's state the one d's block holds, before anything
// reads or advances it: nothing to do if the context wrote it last; a
// block of another coupling (mj_copyData) or an older one of this one is
// taken; a zeroed block (mj_resetData) is the state at rest at d->time.
// Throws std::invalid_argument if the block holds something else or a
// state that cannot be taken.
void ClaimState(CouplingContext* context, const mjData* d) {
  const double* block = d->userdata + context->state_offset;
  const double* header = block + context->state_size - kHeaderSize;
  if (header[3] == kStateTag && header[2] == context->state_size) {
    if (header[0] == context->owner && header[1] == context->writes) return;
    if (context->actuators) {
      try {
        context->actuators->LoadState(d, context->state_offset);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string("d->userdata holds a coupling state that cannot "
                                                "be taken: ") + e.what());
      }
    }
    context->load_history = context->stokes != nullptr;
    WriteState(context, d);
    return;
  }
  bool zero = true;
  for (int k = 0; zero && k < context->state_size; ++k) zero = block[k] == 0.0;
  if (!zero) {
    throw std::invalid_argument(
        "d->userdata[" + std::to_string(context->state_offset) + ", " +
        std::to_string(context->state_offset + context->state_size) +
        ") does not hold the coupling's state (the program wrote there, or copied the data of "
        "another model)");
  }
  if (context->actuators) context->actuators->ResetState(d);
  if (context->stokes) context->stokes->ForgetHistory();
  context->load_history = false;
  WriteState(context, d);
}

void PassiveCallback(const mjModel* m, mjData* d) {
  Registry& registry = GetRegistry();
  if (registry.previous_passive) registry.previous_passive(m, d);
  CouplingContext* context = FindMutableCoupling(d);
  if (!context || !context->Serves(m)) return;
  ++context->passive_calls;
  // The Stokes step asks for the passive forces at zero velocity, where
  // the drag vanishes; it solves for the drag itself.
  if (!context->drag || context->dynamics == Dynamics::kStokes) return;
  try {
    context->fluid->Apply(m, d);
  } catch (const std::exception& e) {
    RecordFailure(context, e.what());
  }
}

void ControlCallback(const mjModel* m, mjData* d) {
  Registry& registry = GetRegistry();
  if (registry.previous_control) registry.previous_control(m, d);
  CouplingContext* context = FindMutableCoupling(d);
  if (!context || !context->Serves(m)) return;
  ++context->control_calls;
  if (!context->actuators) return;
  try {
    ClaimState(context, d);
    context->actuators->Update(m, d);
    WriteState(context, d);
  } catch (const std::exception& e) {
    RecordFailure(context, e.what());
  }
}

void InstallCallbacksOnce(Registry& registry) {
  if (registry.callbacks_installed) return;
  if (mjcb_passive != PassiveCallback) registry.previous_passive = mjcb_passive;
  if (mjcb_control != ControlCallback) registry.previous_control = mjcb_control;
  mjcb_passive = PassiveCallback;
  mjcb_control = ControlCallback;
  registry.callbacks_installed = true;
}

// The context of d with its state claimed (ClaimState).
CouplingContext& RequireCoupling(const mjData* d, const char* function) {
  CouplingContext* context = FindMutableCoupling(d);
  if (!context) {
    throw std::invalid_argument(std::string("ipmc::") + function +
                                ": d is not attached (call ipmc::Attach first)");
  }
  ClaimState(context, d);
  return *context;
}

// The fluid that steps m: its drag acts on m's joints only, so a model
// may leave out what only out-of-plane motions feel when they are planar.
std::unique_ptr<Fluid> MakeSteppingFluid(const mjModel* m, const RftDrag& drag,
                                         const RftDragOverrides& overrides) {
  std::unique_ptr<Fluid> fluid = MakeFluid(m, drag, overrides);
  fluid->set_in_plane_when_planar(true);
  return fluid;
}

// The context Attach couples to a data of m, not yet registered; nullptr
// for a model without ipmc_* fields.
std::unique_ptr<CouplingContext> MakeContext(const mjModel* m,
                                             IpmcActuatorsOverrides overrides,
                                             const RftDragOverrides& fluid, bool for_stepping) {
  if (!HasCustomFieldWithPrefix(m, "ipmc_")) return nullptr;
  std::vector<std::string> known(std::begin(kRftDragFields), std::end(kRftDragFields));
  known.insert(known.end(), IpmcActuatorFields().begin(), IpmcActuatorFields().end());
  known.push_back(kStripWidthField);
  known.push_back(kAttrDynamics);
  for (const std::string& field : FluidModelFields()) known.push_back(field);
  RequireKnownCustomFields(m, "ipmc_", known);
  if (const std::optional<double> width_m = FindCustomScalar(m, kStripWidthField);
      width_m && !(*width_m > 0)) {  // FindCustomScalar refuses a non-finite value
    throw std::invalid_argument(std::string(kStripWidthField) + " must be finite and > 0 m (got " +
                                std::to_string(*width_m) + ")");
  }
  auto context = std::make_unique<CouplingContext>();
  context->model = m;
  context->fluid_overrides = fluid;
  if (std::optional<RftDragConfig> drag = RftDragConfig::FromModel(m, fluid)) {
    context->drag.emplace(m, *drag);
    context->fluid = MakeSteppingFluid(m, *context->drag, fluid);
  }
  if (std::optional<std::string> text = FindCustomText(m, kAttrDynamics)) {
    context->dynamics = ParseDynamics(*text);
  }
  if (overrides.dynamics) context->dynamics = *overrides.dynamics;
  if (for_stepping) {
    context->step = MakeStepModel(m, context->dynamics);
    // The first-order hold of flexible links needs the physical c where
    // the step takes c_eff.
    overrides.physical_damping = context->step.physical_damping;
  }
  if (std::optional<IpmcActuatorsConfig> actuators = IpmcActuatorsConfig::FromModel(m, overrides)) {
    context->actuators = std::make_unique<IpmcActuators>(std::move(*actuators));
  }
  if (context->dynamics == Dynamics::kStokes) context->stokes = std::make_unique<StokesStepper>(m);
  // The history's room is kept in either dynamics, so that the size does
  // not depend on a program's override of it.
  context->state_size =
      ActuatorStateSize(*context) + StokesStepper::HistorySize(m) + kHeaderSize;
  return context;
}

// The failure of a Step of a d that has no context (LastError), kept for
// the thread that stepped it.
struct UnattachedFailure {
  const mjData* d = nullptr;
  std::string error;
};
UnattachedFailure& LastUnattachedFailure() {
  thread_local UnattachedFailure failure;
  return failure;
}

}  // namespace

// The passive and control callbacks, SetVoltages and the runs' readers all
// ask for the context of the mjData their thread steps, several times per
// step. Each thread remembers its last answer and reuses it until the
// registry changes: no lock and no map lookup on a step, and no shared
// cache line written by threads that step different data. A context
// stays where it is while other data are attached or detached (the map
// holds pointers), so only a change of generation requires a new lookup.
CouplingContext* FindMutableCoupling(const mjData* d) {
  struct Lookup {
    const mjData* d = nullptr;
    CouplingContext* context = nullptr;
    unsigned long generation = 0;
    bool valid = false;
  };
  thread_local Lookup last;
  Registry& registry = GetRegistry();
  const unsigned long generation = registry.generation.load(std::memory_order_acquire);
  if (last.valid && last.d == d && last.generation == generation) return last.context;
  std::shared_lock<std::shared_mutex> lock(registry.mutex);
  auto it = registry.contexts.find(d);
  CouplingContext* context = it == registry.contexts.end() ? nullptr : it->second.get();
  // Writers hold the mutex exclusively, so the generation read under the
  // shared lock is the one this answer belongs to.
  last = {d, context, registry.generation.load(std::memory_order_relaxed), true};
  return context;
}

const CouplingContext* FindCoupling(const mjData* d) { return FindMutableCoupling(d); }

bool Attach(const mjModel* m, mjData* d) { return AttachWithOverrides(m, d, {}); }

bool AttachWithOverrides(const mjModel* m, mjData* d, const IpmcActuatorsOverrides& overrides,
                         const RftDragOverrides& fluid) {
  std::unique_ptr<CouplingContext> context = MakeContext(m, overrides, fluid, true);
  if (!context) return false;
  if (m->nuserdata < context->state_size) {
    throw std::invalid_argument(
        "the model has nuserdata = " + std::to_string(m->nuserdata) +
        "; the coupling keeps its state in the last " + std::to_string(context->state_size) +
        " values of mjData.userdata: declare <size nuserdata=\"" +
        std::to_string(context->state_size) +
        "\"/> (more if the program uses userdata too) in the MJCF, or set m->nuserdata = "
        "ipmc::UserdataSize(m) before mj_makeData");
  }
  context->state_offset = m->nuserdata - context->state_size;
  Registry& registry = GetRegistry();
  context->owner = static_cast<double>(++registry.couplings);
  // The state d holds (a copy of an attached mjData, or d's own under its
  // last coupling), or rest for a d never attached.
  ClaimState(context.get(), d);
  std::unique_lock<std::shared_mutex> lock(registry.mutex);
  InstallCallbacksOnce(registry);
  registry.contexts[d] = std::move(context);
  registry.generation.fetch_add(1, std::memory_order_release);
  return true;
}

int UserdataSizeWithOverrides(const mjModel* m, const IpmcActuatorsOverrides& overrides,
                              const RftDragOverrides& fluid) {
  const std::unique_ptr<CouplingContext> context = MakeContext(m, overrides, fluid, false);
  return context ? context->state_size : 0;
}

int UserdataSize(const mjModel* m) { return UserdataSizeWithOverrides(m, {}); }

bool Detach(const mjData* d) {
  Registry& registry = GetRegistry();
  std::unique_lock<std::shared_mutex> lock(registry.mutex);
  const bool erased = registry.contexts.erase(d) > 0;
  if (erased) registry.generation.fetch_add(1, std::memory_order_release);
  return erased;
}

int SetVoltages(const mjData* d, const double* voltage_V, int count) {
  CouplingContext* context = FindMutableCoupling(d);
  if (!context || !context->actuators) return 0;
  ClaimState(context, d);
  context->actuators->SetVoltages(d, std::vector<double>(voltage_V, voltage_V + count));
  WriteState(context, d);
  return context->actuators->Links();
}

CouplingState SaveState(const mjData* d) {
  CouplingContext& context = RequireCoupling(d, "SaveState");
  if (!context.actuators) return {};
  CouplingState state = context.actuators->SaveState();
  WriteState(&context, d);
  return state;
}

void RestoreState(const mjData* d, const CouplingState& state) {
  CouplingContext& context = RequireCoupling(d, "RestoreState");
  if (context.actuators) {
    context.actuators->RestoreState(d, state);
    WriteState(&context, d);
    return;
  }
  if (!state.actuator_state.empty() || !state.voltage_V.empty() || !state.curvature_1_m.empty()) {
    throw std::invalid_argument(
        "ipmc::RestoreState: actuator_state, voltage_V and curvature_1_m must be empty: d's model "
        "has no IPMC actuators");
  }
}

void ResetState(const mjData* d) {
  CouplingContext& context = RequireCoupling(d, "ResetState");
  if (context.actuators) context.actuators->ResetState(d);
  WriteState(&context, d);
}

// The CMake project version (plugin/CMakeLists.txt), the one source of
// every version string: `ipmc-swim --version`, summary.json, Python.
const char* Version() { return IPMC_SWIM_VERSION; }

namespace {

// A callback that did not run during a step for d was replaced by the
// host after Attach: warn once (the drag or the actuators are off).
void WarnIfCallbackReplaced(CouplingContext* context, unsigned long passive_before,
                            unsigned long control_before) {
  if (context->warned_replaced_callback) return;
  const char* which = nullptr;
  if (context->drag && context->passive_calls == passive_before) which = "mjcb_passive";
  if (context->actuators && context->control_calls == control_before) which = "mjcb_control";
  if (!which) return;
  context->warned_replaced_callback = true;
  mju_warning_s("ipmc_swim: %s was replaced after ipmc::Attach: the coupling's drag or "
                "actuators are off (chain to the previous callback or Attach again)",
                which);
}

}  // namespace

namespace {

// MuJoCo's checks of the state in mj_step (mj_checkPos and mj_checkVel
// before the forward pass, mj_checkAcc after it) and of the controls in
// mj_fwdActuation: each counts a warning with the offending index in
// lastinfo; all but the controls' then reset d to the model's initial
// state (mj_resetData), which leaves the count at 1 and d->time at 0.
struct BadStateCheck {
  mjtWarning warning;
  const char* what;
  mjtObj indexed;  // what lastinfo indexes: a qpos address, a dof, an actuator
};
constexpr BadStateCheck kBadStateChecks[] = {
    {mjWARN_BADQPOS, "position (qpos)", mjOBJ_UNKNOWN},
    {mjWARN_BADQVEL, "velocity (qvel)", mjOBJ_DOF},
    {mjWARN_BADQACC, "acceleration (qacc)", mjOBJ_DOF},
    {mjWARN_BADCTRL, "control (ctrl)", mjOBJ_ACTUATOR}};
constexpr int kBadStateCheckCount = sizeof(kBadStateChecks) / sizeof(kBadStateChecks[0]);

// The joint of qpos address `address`.
int JointOfQpos(const mjModel* m, int address) {
  int joint = -1;
  for (int j = 0; j < m->njnt && m->jnt_qposadr[j] <= address; ++j) joint = j;
  return joint;
}

// "dof 3 (joint 'j2')", "qpos[4] (joint 'j3')", "actuator 2 ('ipmc_j2')".
std::string Located(const mjModel* m, mjtObj indexed, int index) {
  const auto named = [&](mjtObj type, int id) {
    const char* name = id >= 0 ? mj_id2name(m, type, id) : nullptr;
    return name ? std::string("'") + name + "'" : "#" + std::to_string(id);
  };
  switch (indexed) {
    case mjOBJ_DOF:
      if (index < 0 || index >= m->nv) return "dof " + std::to_string(index);
      return "dof " + std::to_string(index) + " (joint " +
             named(mjOBJ_JOINT, m->dof_jntid[index]) + ")";
    case mjOBJ_ACTUATOR:
      return "actuator " + std::to_string(index) + " (" + named(mjOBJ_ACTUATOR, index) + ")";
    default:
      if (index < 0 || index >= m->nq) return "qpos[" + std::to_string(index) + "]";
      return "qpos[" + std::to_string(index) + "] (joint " +
             named(mjOBJ_JOINT, JointOfQpos(m, index)) + ")";
  }
}

std::string DivergedAt(const mjModel* m, double start_s, const std::string& what) {
  char head[80], tail[120];
  std::snprintf(head, sizeof(head), "%s%.9g s: ", kDivergedPrefix, start_s);
  std::snprintf(tail, sizeof(tail), " (reduce option timestep, now %.9g s, or the inputs' size)",
                m->opt.timestep);
  return head + what + tail;
}

// What of d is not finite or beyond MuJoCo's limit mjMAXVAL after a step
// (mju_isBad), or a link's free deflection that is not finite; "" if
// nothing. O(nq + nv + links): cheap beside the step.
std::string BadState(const mjModel* m, const mjData* d, const IpmcActuators* actuators) {
  for (int i = 0; i < m->nq; ++i) {
    if (mju_isBad(d->qpos[i])) {
      return "the position " + Located(m, mjOBJ_UNKNOWN, i) +
             " is not finite or beyond MuJoCo's limit";
    }
  }
  for (int i = 0; i < m->nv; ++i) {
    if (mju_isBad(d->qvel[i])) {
      return "the velocity of " + Located(m, mjOBJ_DOF, i) +
             " is not finite or beyond MuJoCo's limit";
    }
  }
  if (actuators) {
    for (int q = 0; q < actuators->Links(); ++q) {
      if (!std::isfinite(actuators->FreeTipDeflection_mm(q))) {
        return "the free tip deflection of IPMC link " + std::to_string(q + 1) + " (joint '" +
               actuators->joints()[q] + "') is not finite";
      }
    }
  }
  return "";
}

// The counts of MuJoCo's bad-state warnings before a step.
struct BadStateCounts {
  int number[kBadStateCheckCount];
};

BadStateCounts CountBadStates(const mjData* d) {
  BadStateCounts counts;
  for (int k = 0; k < kBadStateCheckCount; ++k) {
    counts.number[k] = d->warning[kBadStateChecks[k].warning].number;
  }
  return counts;
}

// The divergence an inertial step from start_s met, "" if none: a
// bad-state warning counted during it (or counted at all when the step did
// not end at start_s + h: MuJoCo reset d, clearing the counts).
std::string InertialStepDiverged(const mjModel* m, const mjData* d, double start_s,
                                 const BadStateCounts& before) {
  const bool reset = d->time != start_s + m->opt.timestep;
  for (int k = 0; k < kBadStateCheckCount; ++k) {
    const mjWarningStat& stat = d->warning[kBadStateChecks[k].warning];
    if (stat.number > before.number[k] || (reset && stat.number > 0)) {
      return std::string("MuJoCo found a bad ") + kBadStateChecks[k].what + " at " +
             Located(m, kBadStateChecks[k].indexed, stat.lastinfo) +
             (kBadStateChecks[k].warning == mjWARN_BADCTRL ? " and zeroed it"
                                                           : " and reset the data");
    }
  }
  return "";
}

}  // namespace

namespace {
// One step of an attached d with the coupling's step model m.
bool StepAttached(const mjModel* m, mjData* d, CouplingContext* context);
}  // namespace

bool Step(const mjModel* m, mjData* d) { return Step(m, d, StepSettings{}); }

bool Step(const mjModel* m, mjData* d, const StepSettings& options) {
  CouplingContext* context = FindMutableCoupling(d);
  if (!context || context->model != m) {
    const bool coupled_model = HasCustomFieldWithPrefix(m, "ipmc_") ||
                               (m->nuserdata > 0 && d->userdata[m->nuserdata - 1] == kStateTag);
    if (!coupled_model) {
      mj_step(m, d);
      return true;
    }
    // Stepped by mj_step, d would run without drag and actuators.
    UnattachedFailure& failure = LastUnattachedFailure();
    failure.d = d;
    failure.error = context ? "d is attached with another mjModel than m"
                            : "d is not attached (mj_copyData and mj_makeData do not attach: "
                              "call ipmc::Attach(m, d), which takes the state d holds)";
    return false;
  }
  context->error.clear();
  if (!std::isfinite(d->time)) {
    context->error = "d->time is " + std::string(std::isnan(d->time) ? "NaN" : "infinite") +
                     " (it must be finite)";
    return false;
  }
  try {
    ClaimState(context, d);
  } catch (const std::invalid_argument& e) {
    context->error = e.what();
    return false;
  }
  // The model the coupling steps d with: m as it is now, with the
  // coupling's numerical choices (plugin/dynamics/step_model.h).
  RefreshStepModel(&context->step, m, context->dynamics);
  mjModel* step_model = context->step.model.get();
  if (context->load_history) {
    context->stokes->LoadHistory(step_model, d, context->fluid.get(),
                                 context->state_offset + ActuatorStateSize(*context));
    context->load_history = false;
  }
  const int flags = step_model->opt.disableflags;
  if (!options.compute_sensors) step_model->opt.disableflags = flags | mjDSBL_SENSOR;
  const bool stepped = StepAttached(step_model, d, context);
  step_model->opt.disableflags = flags;
  return stepped;
}

namespace {

bool StepAttached(const mjModel* m, mjData* d, CouplingContext* context) {
  const double start_s = d->time;
  const unsigned long passive_before = context->passive_calls;
  const unsigned long control_before = context->control_calls;
  std::string diverged;
  if (context->stokes && (mjcb_passive != PassiveCallback || GetRegistry().previous_passive)) {
    context->error =
        "dynamics = stokes: a host mjcb_passive is set, whose forces the Stokes force balance "
        "does not take (refused; apply them as actuator forces, or use inertial dynamics)";
    return false;
  }
  if (context->stokes) {
    // Checked before the step as mj_step's mj_checkPos and mj_checkVel
    // do (the step replaces the velocity, but a bad one is a mistake).
    if (std::string bad = BadState(m, d, nullptr); !bad.empty()) {
      context->error = DivergedAt(m, start_s, bad);
      return false;
    }
    if (!context->stokes->Step(m, d, context->fluid.get()) && context->error.empty()) {
      context->error =
          "dynamics = stokes: the force balance is singular (a dof has neither drag nor "
          "joint damping or stiffness)";
    }
  } else {
    const BadStateCounts before = CountBadStates(d);
    if (context->actuators) context->actuators->BeginInertialStep(m);
    mj_step(m, d);
    if (context->actuators) context->actuators->EndInertialStep();
    diverged = InertialStepDiverged(m, d, start_s, before);
  }
  if (diverged.empty() && context->error.empty()) {
    diverged = BadState(m, d, context->actuators.get());
  }
  if (!context->error.empty()) {
    char head[80];
    std::snprintf(head, sizeof(head), "step at t = %.9g s failed: ", start_s);
    context->error.insert(0, head);
  } else if (!diverged.empty()) {
    context->error = DivergedAt(m, start_s, diverged);
  }
  if (context->error.empty()) WriteState(context, d);
  WarnIfCallbackReplaced(context, passive_before, control_before);
  return context->error.empty();
}

}  // namespace

namespace {

// The coupling of d, with `link` one of its links (`function` names the
// caller in the message).
const CouplingContext& RequireLinkOf(const mjData* d, int link, const char* function) {
  const CouplingContext& context = RequireCoupling(d, function);
  const int links = context.actuators ? context.actuators->Links() : 0;
  if (link < 0 || link >= links) {
    throw std::invalid_argument(std::string("ipmc::") + function + ": link " +
                                std::to_string(link) + " is outside [0, " +
                                std::to_string(links - 1) + "] (the model's ipmc_links)");
  }
  return context;
}

// The fluid's wrenches [torque; force] on each body (world frame, about
// the subtree centre of mass of its root: MuJoCo's cvel convention), and
// the velocities V they act on, from d's qpos and qvel.
struct FluidWrenches {
  std::vector<Eigen::Matrix<double, 6, 1>> wrench, velocity;
  std::vector<bool> acted;
  mjData* c = nullptr;  // the scratch data they were computed on
};

FluidWrenches ComputeFluidWrenches(CouplingContext& context, const mjData* d) {
  const mjModel* m = context.step.model.get();
  if (!context.scratch) context.scratch.reset(mj_makeData(m));
  FluidWrenches out;
  mjData* c = out.c = context.scratch.get();
  mju_copy(c->qpos, d->qpos, m->nq);
  mju_copy(c->qvel, d->qvel, m->nv);
  c->time = d->time;
  mj_kinematics(m, c);
  mj_comPos(m, c);
  mj_comVel(m, c);
  out.wrench.assign(m->nbody, Eigen::Matrix<double, 6, 1>::Zero());
  out.velocity.resize(m->nbody);
  out.acted.assign(m->nbody, false);
  for (int b = 0; b < m->nbody; ++b) {
    out.velocity[b] = Eigen::Map<const Eigen::Matrix<double, 6, 1>>(c->cvel + 6 * b);
  }
  BodyResistanceBlocks<6> spatial;
  context.fluid->LocalResistances(m, c, &spatial);
  for (const BodyResistanceBlock<6>& block : spatial) {
    out.wrench[block.body] -= block.resistance * out.velocity[block.body];
    out.acted[block.body] = true;
  }
  if (spatial.empty()) {
    // A planar fluid's blocks: [w_z; v_x; v_y], components 2..4.
    BodyResistanceBlocks<3> planar;
    context.fluid->LocalResistances(m, c, &planar);
    for (const BodyResistanceBlock<3>& block : planar) {
      out.wrench[block.body].segment<3>(2) -=
          block.resistance * out.velocity[block.body].segment<3>(2);
      out.acted[block.body] = true;
    }
  }
  if (const Eigen::MatrixXd* resistance = context.fluid->InteractionResistance(m, c)) {
    const std::vector<int>& bodies = context.fluid->InteractingBodies();
    Eigen::VectorXd velocity(6 * bodies.size());
    for (size_t i = 0; i < bodies.size(); ++i) velocity.segment<6>(6 * i) = out.velocity[bodies[i]];
    const Eigen::VectorXd wrench = -(*resistance) * velocity;
    for (size_t i = 0; i < bodies.size(); ++i) {
      out.wrench[bodies[i]] += wrench.segment<6>(6 * i);
      out.acted[bodies[i]] = true;
    }
  }
  return out;
}

}  // namespace

bool IsAttached(const mjData* d) { return FindCoupling(d) != nullptr; }

int LinkCount(const mjData* d) {
  const CouplingContext& context = RequireCoupling(d, "LinkCount");
  return context.actuators ? context.actuators->Links() : 0;
}

std::vector<int> LinkJoints(const mjData* d, int link) {
  const CouplingContext& context = RequireLinkOf(d, link, "LinkJoints");
  return context.actuators->chains()[link].joints;
}

double LinkVoltage_V(const mjData* d, int link) {
  const CouplingContext& context = RequireLinkOf(d, link, "LinkVoltage_V");
  return context.actuators->Voltages_V()[link];
}

std::vector<double> LinkActiveMoments_N_m(const mjData* d, int link) {
  const CouplingContext& context = RequireLinkOf(d, link, "LinkActiveMoments_N_m");
  std::vector<double> moments_N_m;
  for (int motor : context.actuators->chains()[link].motors) moments_N_m.push_back(d->ctrl[motor]);
  return moments_N_m;
}

std::vector<double> LinkSegmentLengths_m(const mjData* d, int link) {
  const CouplingContext& context = RequireLinkOf(d, link, "LinkSegmentLengths_m");
  return context.actuators->chains()[link].segment_length_m;
}

double LinkLength_m(const mjData* d, int link) {
  const CouplingContext& context = RequireLinkOf(d, link, "LinkLength_m");
  return context.actuators->chains()[link].length_m;
}

double LinkFreeDeflection_mm(const mjData* d, int link) {
  const CouplingContext& context = RequireLinkOf(d, link, "LinkFreeDeflection_mm");
  return context.actuators->FreeTipDeflection_mm(link);
}

long ClampCount(const mjData* d) {
  const CouplingContext& context = RequireCoupling(d, "ClampCount");
  return context.actuators ? context.actuators->ClampCount() : 0;
}

namespace {
OustaloupBand BandOf(const OustaloupConfig& config) {
  OustaloupBand band;
  band.order = config.order;
  band.low_rad_s = config.w_low_rad_s;
  band.high_rad_s = config.w_high_rad_s;
  band.pairs = config.n;
  band.two_n_plus_one = config.variant == OustaloupVariant::k2NPlus1;
  return band;
}
}  // namespace

LinkPlantParameters LinkPlantOf(const mjData* d, int link) {
  const CouplingContext& context = RequireLinkOf(d, link, "LinkPlantOf");
  const IpmcLinkParams& params = context.actuators->link_params()[link];
  LinkPlantParameters plant;
  plant.g2 = params.kind == IpmcModelKind::kG2;
  plant.a0_mm_per_V = params.a0_mm_per_V;
  plant.b1 = params.b1;
  plant.b2_s2 = params.b2_s2;
  plant.alpha = params.alpha;
  plant.integrator = BandOf(params.integrator);
  plant.fractional_lag = BandOf(params.fractional_lag);
  return plant;
}

MomentHold LinkMomentHold(const mjData* d, int link) {
  const CouplingContext& context = RequireLinkOf(d, link, "LinkMomentHold");
  const IpmcActuators& actuators = *context.actuators;
  MomentHold hold;
  hold.first_order = actuators.FirstOrderHold() && context.dynamics == Dynamics::kInertial;
  const std::vector<double>& start_N_m = actuators.StepStartMoments_N_m();
  const std::vector<double>& end_N_m = actuators.StepEndMoments_N_m();
  if (!hold.first_order || end_N_m.empty()) return hold;
  for (int motor : actuators.chains()[link].motors) {
    hold.start_N_m.push_back(start_N_m[motor]);
    hold.end_N_m.push_back(end_N_m[motor]);
  }
  return hold;
}

bool StokesDynamics(const mjData* d) {
  return RequireCoupling(d, "StokesDynamics").dynamics == Dynamics::kStokes;
}

std::vector<double> StepDamping(const mjModel* m, const mjData* d) {
  const CouplingContext& context = RequireCoupling(d, "StepDamping");
  if (!context.Serves(m)) {
    throw std::invalid_argument("ipmc::StepDamping: d is attached with another mjModel than m");
  }
  const mjModel* step = context.step.model.get();
  return std::vector<double>(step->dof_damping, step->dof_damping + step->nv);
}

double StepFluidPower_W(const mjModel* m, const mjData* d) {
  const CouplingContext& context = RequireCoupling(d, "StepFluidPower_W");
  if (context.stokes) return context.stokes->fluid_power_W();
  return context.fluid ? context.fluid->DissipatedPower_W(m, d) : 0.0;
}

FluidFacts FluidOf(const mjData* d) {
  const CouplingContext& context = RequireCoupling(d, "FluidOf");
  FluidFacts facts;
  if (!context.fluid) return facts;
  const Fluid& fluid = *context.fluid;
  facts.drag = true;
  facts.viscosity_Pa_s = fluid.Viscosity_Pa_s();
  facts.density_kg_m3 = fluid.FluidDensity_kg_m3();
  facts.segment_length_m = fluid.SegmentLengths_m();
  facts.strip_width_m = StripWidth_m(context.model);
  facts.towing_drag_N_s_m = fluid.TowingDrag_N(1.0);
  facts.rotational_drag_N_m_s = fluid.RotationalDragScale_N_m_s();
  return facts;
}

ResistanceEvaluations FluidResistanceEvaluations(const mjData* d) {
  const CouplingContext& context = RequireCoupling(d, "FluidResistanceEvaluations");
  ResistanceEvaluations evaluations;
  if (const auto* dense = dynamic_cast<const DenseResistanceFluid*>(context.fluid.get())) {
    evaluations.exact = dense->recomputations();
    evaluations.fitted = dense->fits();
  }
  return evaluations;
}

std::vector<double> DragMatrix(const mjModel* m, const mjData* d) {
  const CouplingContext& context = RequireCoupling(d, "DragMatrix");
  if (!context.Serves(m)) {
    throw std::invalid_argument("ipmc::DragMatrix: d is attached with another mjModel than m");
  }
  if (!context.fluid) return {};
  const int nv = m->nv;
  const std::unique_ptr<mjData, void (*)(mjData*)> copy(mj_makeData(m), mj_deleteData);
  mjData* c = copy.get();
  mj_copyData(c, m, d);
  mju_zero(c->qvel, nv);
  mj_fwdPosition(m, c);
  // Column j: the drag of a unit velocity of dof j (the drag is linear in
  // the velocities).
  std::vector<double> drag(static_cast<size_t>(nv) * nv);
  for (int j = 0; j < nv; ++j) {
    mju_zero(c->qvel, nv);
    c->qvel[j] = 1.0;
    mj_comVel(m, c);
    mju_zero(c->qfrc_passive, nv);
    context.fluid->Apply(m, c);
    for (int i = 0; i < nv; ++i) drag[static_cast<size_t>(i) * nv + j] = -c->qfrc_passive[i];
  }
  return drag;
}

std::vector<BodyFluidForce> FluidForces(const mjModel* m, const mjData* d) {
  CouplingContext& context = RequireCoupling(d, "FluidForces");
  if (!context.Serves(m)) {
    throw std::invalid_argument("ipmc::FluidForces: d is attached with another mjModel than m");
  }
  if (!context.fluid) return {};
  const FluidWrenches wrenches = ComputeFluidWrenches(context, d);
  const mjModel* sm = context.step.model.get();
  std::vector<BodyFluidForce> forces;
  for (int b = 0; b < sm->nbody; ++b) {
    if (!wrenches.acted[b]) continue;
    // The torque about the body's origin x: T_x = T_p + (p - x) x F.
    const Eigen::Vector3d p(wrenches.c->subtree_com + 3 * sm->body_rootid[b]);
    const Eigen::Vector3d x(wrenches.c->xpos + 3 * b);
    const Eigen::Vector3d force = wrenches.wrench[b].tail<3>();
    const Eigen::Vector3d torque = wrenches.wrench[b].head<3>() + (p - x).cross(force);
    BodyFluidForce entry;
    entry.body = b;
    for (int k = 0; k < 3; ++k) {
      entry.force_N[k] = force[k];
      entry.torque_N_m[k] = torque[k];
    }
    forces.push_back(entry);
  }
  return forces;
}

double FluidPower_W(const mjModel* m, const mjData* d) {
  CouplingContext& context = RequireCoupling(d, "FluidPower_W");
  if (!context.Serves(m)) {
    throw std::invalid_argument("ipmc::FluidPower_W: d is attached with another mjModel than m");
  }
  if (!context.fluid) return 0.0;
  const FluidWrenches wrenches = ComputeFluidWrenches(context, d);
  double power_W = 0.0;
  for (size_t b = 0; b < wrenches.wrench.size(); ++b) {
    power_W -= wrenches.wrench[b].dot(wrenches.velocity[b]);
  }
  return power_W;
}

void SetFluidField(const mjData* d, const char* field, double value) {
  CouplingContext& context = RequireCoupling(d, "SetFluidField");
  const std::string name = field ? field : "";
  mjModel* m = context.step.model.get();
  const int id = mj_name2id(m, mjOBJ_NUMERIC, name.c_str());
  const bool fluid_field = name.rfind("ipmc_rft_", 0) == 0 || name.rfind("ipmc_fluid_", 0) == 0;
  if (!fluid_field || id < 0 || m->numeric_size[id] != 1) {
    throw std::invalid_argument("ipmc::SetFluidField: '" + name +
                                "' is not a one-value ipmc_rft_* or ipmc_fluid_* numeric of "
                                "the model (declare it in the model's <custom>)");
  }
  mjtNum& slot = m->numeric_data[m->numeric_adr[id]];
  const mjtNum old = slot;
  slot = value;
  // Checked on a trial drag first (a fluid may refer to its segments), so
  // that a refused value leaves d's coupling as it was.
  std::optional<RftDragConfig> config;
  try {
    config = RftDragConfig::FromModel(m, context.fluid_overrides);
    if (!config) throw std::invalid_argument("the model has no drag");
    const RftDrag trial(m, *config);
    MakeFluid(m, trial, context.fluid_overrides);
  } catch (const std::exception& e) {
    slot = old;
    throw std::invalid_argument(std::string("ipmc::SetFluidField: ") + e.what());
  }
  context.fluid.reset();
  context.drag.emplace(m, *config);
  context.fluid = MakeSteppingFluid(m, *context.drag, context.fluid_overrides);
  if (context.stokes) context.stokes->ForgetHistory();
}

const char* LastError(const mjData* d) {
  if (const CouplingContext* context = FindCoupling(d)) return context->error.c_str();
  const UnattachedFailure& failure = LastUnattachedFailure();
  return failure.d == d ? failure.error.c_str() : "";
}


}  // namespace ipmc
