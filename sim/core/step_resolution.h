// Whether an inertial run's time step is small enough for its swim: MuJoCo's
// step (Euler, or implicit, which differs from Euler only in actuator and
// tendon terms, sim/core/simulation.h) takes the fluid's drag (the
// coupling's passive callback) explicitly, at the step's start. The Stokes
// step (plugin/dynamics/stokes_step.h) takes it implicitly, at the step's
// midpoint, and has neither limit below.
//
//   drag relaxation   tau_D = 1 / lambda_max(M^-1 D) at the body's rest
//                     shape (M the joint-space mass matrix, mj_fullM; D the
//                     fluid's force on unit joint velocities); for one
//                     segment of mass m, normal drag coefficient xi_n and
//                     length L, m / (xi_n L). Explicit Euler on the drag
//                     alone is unstable beyond h = 2 tau_D.
//   the swim's error  the drag a step behind the motion shifts the forces'
//                     phase by about omega h; the swim, second order in the
//                     motion, moves by that phase times its own scale per
//                     cycle, A^2 / L (A = v_tip / omega the tip's amplitude,
//                     L the body's length), against the swim per cycle
//                     U / f:
//                       e = kappa h v_tip^2 / (2 pi L |U|)
//                     first order in h, with kappa measured (below).
#pragma once

#include <mujoco/mujoco.h>

#include <cmath>
#include <string>
#include <vector>

namespace ipmc {

// kappa above: the measured swim error over h v_tip^2 / (2 pi L |U|) of
// every run of docs/RUNS.md ("The step's own error"), each against its
// step-converged swim (first-order Richardson from its two finest steps):
// 3.6 for the two-link strip of docs/OWN_ROBOT.md at 1 Hz in water, 4.6 in
// a 1 Pa s oil (10 us to 1.25 us), 7.6 for the paper's run (0.5 ms),
// 2.9 to 6.0 at 0.02 and 0.04 Hz with c1 = 100 and 250 um/mm. 10 is above
// them all, so the estimate bounds the error from above.
constexpr double kSwimStepErrorConstant = 10.0;
// The largest estimated swim error that passes.
constexpr double kMaxSwimStepError = 0.01;
// The largest step per drag relaxation: the paper's strip in a 1 Pa s oil
// at 0.5 ms (h / tau 0.86) is 2e-4 from its swim at 0.125 ms.
constexpr double kMaxStepPerDragRelaxation = 1.0;

struct StepResolution {
  bool explicit_drag = false;           // the run steps inertially (mj_step)
  double timestep_s = 0.0;
  double drag_relaxation_s = INFINITY;  // tau_D; infinite without drag
  double swim_error = 0.0;              // e above, relative; 0 before the swim is known
  // The largest step whose e is at most kMaxSwimStepError and h / tau_D
  // at most kMaxStepPerDragRelaxation (timestep_s itself if it passes).
  double resolving_timestep_s = 0.0;
  bool Resolved() const;
};

// Measures m's drag relaxation at d's positions (d itself is not changed).
// A model that steps with the Stokes step, or without a coupled fluid, or
// a run without a frequency, gives explicit_drag = false (and no warning).
StepResolution MeasureStepResolution(const mjModel* m, const mjData* d, double frequency_Hz);

// `step` with the swim's error e of a run whose last tip peaked at
// `peak_tip_speed_mm_s` across the axis, on a body of `body_length_mm`,
// swimming at `mean_speed_mm_s` (e = 0 for a body that does not swim),
// and the step that resolves both.
StepResolution WithSwimStepError(StepResolution step, double peak_tip_speed_mm_s,
                                 double body_length_mm, double mean_speed_mm_s);

// The warning for a step that does not resolve the swim (none if it does):
// names the step to use and dynamics = "stokes". `controller_rate_Hz` > 0
// rounds the step down to a whole number per controller sample.
std::vector<std::string> StepResolutionWarnings(const StepResolution& step,
                                                double controller_rate_Hz = 0.0);

}  // namespace ipmc
