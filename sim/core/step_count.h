// The number of fixed time steps an interval takes, checked: a run whose
// step count rounds to zero, or is too large to finish, would otherwise
// "succeed" with empty or never-ending output.
#pragma once

#include <string>

namespace ipmc {

// Most steps one interval (a wave cycle, a bench experiment) may take:
// 1e9 steps of this model take hours at the measured ~10 us per step.
constexpr double kMaxStepsPerInterval = 1e9;

// round(interval_s / timestep_s), at least `min_steps`. Throws
// std::invalid_argument naming `what` (e.g. "scenario.toml: one wave cycle")
// when the time step is not finite and > 0, the interval is not finite and
// > 0, or the count is outside [min_steps, kMaxStepsPerInterval].
long CheckedStepCount(double interval_s, double timestep_s, long min_steps, const std::string& what);

}  // namespace ipmc
