// The controller as scenario keys: [controller], the kind and what every
// kind shares (sample rate, voltage limit, clamp), the PID's gains (eq. 12)
// and the fractional integrator's (eq. 13-15), each one value for every
// link or one per link; and the scenario's controller part those keys set.
#pragma once

#include <vector>

#include "controllers/fractional_integrator.h"
#include "controllers/pid.h"
#include "sim/core/choice_table.h"
#include "sim/core/scenario_keys.h"

namespace ipmc {

enum class ControllerKind { kPid, kFractional };

inline constexpr ChoiceName<ControllerKind> kControllerKindNames[] = {
    {"pid", ControllerKind::kPid},
    {"fractional", ControllerKind::kFractional},
};

// [controller]. The chosen kind's Config is validated by its own
// Validate() (controllers/pid.h, controllers/fractional_integrator.h) once
// the scenario is read, its sample period set from sample_rate_Hz; a
// whole number of time steps per sample is checked with the run's time
// step (sim/core/scenario.cc).
struct ControllerScenario {
  ControllerKind kind = ControllerKind::kPid;
  double sample_rate_Hz = 1000.0;
  PidController::Config pid;  // sample period, clamp set from the fields above
  FractionalIntegrator::Config fractional;
  // Per-link gains, one per link in order (empty: every link takes the one
  // above): what an optimisation that retunes each design's controllers
  // sets (docs/OPTIMIZE.md).
  struct LinkGains {
    std::vector<double> kp, ki, kd;   // PID [V/mm], [V/(mm s)], [V s/mm]
    std::vector<double> gain, order;  // fractional [V/(mm s^lambda)], lambda
  } link_gains;

  // Both kinds' sample period, 1 / sample_rate_Hz.
  void SetSamplePeriod();
  // Link q's (0-based) Config: the scalar keys' with that link's gains
  // where link_gains gives them (one per link: CheckLinkGains,
  // sim/runs/closed_loop_run.h). What the run's controllers and the
  // exported code (sim/identify/controller_export.h) are made from.
  PidController::Config LinkPid(int q) const;
  FractionalIntegrator::Config LinkFractional(int q) const;
  // The chosen kind's Config: FieldError naming the field, or
  // std::invalid_argument.
  void Validate() const;
};

// The [controller] keys of the key table, in its order.
std::vector<KeySpec> ControllerKeys();

}  // namespace ipmc
