#include "plugin/coupling.h"

#include <mutex>
#include <shared_mutex>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "ipmc_swim/ipmc_swim.h"
#include "plugin/mjcf/custom_fields.h"

namespace ipmc {
namespace {

// Registry of contexts keyed by mjData. Written by Attach/Detach, read by
// the callbacks; a shared mutex lets many threads step at once.
struct Registry {
  std::shared_mutex mutex;
  std::unordered_map<const mjData*, std::unique_ptr<CouplingContext>> contexts;
  bool callbacks_installed = false;
  mjfGeneric previous_passive = nullptr;
  mjfGeneric previous_control = nullptr;
};

Registry& GetRegistry() {
  static Registry registry;
  return registry;
}

void PassiveCallback(const mjModel* m, mjData* d) {
  Registry& registry = GetRegistry();
  if (registry.previous_passive) registry.previous_passive(m, d);
  const CouplingContext* context = FindCoupling(d);
  if (context && context->model == m && context->drag) context->drag->Apply(m, d);
}

void ControlCallback(const mjModel* m, mjData* d) {
  Registry& registry = GetRegistry();
  if (registry.previous_control) registry.previous_control(m, d);
  CouplingContext* context = FindMutableCoupling(d);
  if (context && context->model == m && context->actuators) context->actuators->Update(m, d);
}

void InstallCallbacksOnce(Registry& registry) {
  if (registry.callbacks_installed) return;
  if (mjcb_passive != PassiveCallback) registry.previous_passive = mjcb_passive;
  if (mjcb_control != ControlCallback) registry.previous_control = mjcb_control;
  mjcb_passive = PassiveCallback;
  mjcb_control = ControlCallback;
  registry.callbacks_installed = true;
}

CouplingContext& RequireCoupling(const mjData* d, const char* function) {
  CouplingContext* context = FindMutableCoupling(d);
  if (!context) {
    throw std::invalid_argument(std::string("ipmc::") + function +
                                ": d is not attached (call ipmc::Attach first)");
  }
  return *context;
}

}  // namespace

CouplingContext* FindMutableCoupling(const mjData* d) {
  Registry& registry = GetRegistry();
  std::shared_lock<std::shared_mutex> lock(registry.mutex);
  auto it = registry.contexts.find(d);
  return it == registry.contexts.end() ? nullptr : it->second.get();
}

const CouplingContext* FindCoupling(const mjData* d) { return FindMutableCoupling(d); }

bool Attach(const mjModel* m, mjData* d) { return AttachWithOverrides(m, d, {}); }

bool AttachWithOverrides(const mjModel* m, mjData* d, const IpmcActuatorsOverrides& overrides) {
  if (!HasCustomFieldWithPrefix(m, "ipmc_")) return false;
  auto context = std::make_unique<CouplingContext>();
  context->model = m;
  if (std::optional<RftDragConfig> drag = RftDragConfig::FromModel(m)) {
    context->drag.emplace(m, *drag);
  }
  if (std::optional<IpmcActuatorsConfig> actuators = IpmcActuatorsConfig::FromModel(m, overrides)) {
    context->actuators = std::make_unique<IpmcActuators>(std::move(*actuators));
    context->actuators->ResetState(d);  // at rest at d->time
  }
  Registry& registry = GetRegistry();
  std::unique_lock<std::shared_mutex> lock(registry.mutex);
  InstallCallbacksOnce(registry);
  registry.contexts[d] = std::move(context);
  return true;
}

bool Detach(const mjData* d) {
  Registry& registry = GetRegistry();
  std::unique_lock<std::shared_mutex> lock(registry.mutex);
  return registry.contexts.erase(d) > 0;
}

int SetVoltages(const mjData* d, const double* voltage_V, int count) {
  CouplingContext* context = FindMutableCoupling(d);
  if (!context || !context->actuators) return 0;
  context->actuators->SetVoltages(d, std::vector<double>(voltage_V, voltage_V + count));
  return context->actuators->Links();
}

CouplingState SaveState(const mjData* d) {
  CouplingContext& context = RequireCoupling(d, "SaveState");
  if (!context.actuators) return {};
  return context.actuators->SaveState();
}

void RestoreState(const mjData* d, const CouplingState& state) {
  CouplingContext& context = RequireCoupling(d, "RestoreState");
  if (context.actuators) {
    context.actuators->RestoreState(d, state);
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
}

const char* Version() { return "0.1.0"; }

}  // namespace ipmc
