// Whether an inertial run's time step resolves the motion it integrates
// explicitly: MuJoCo's step (Euler, or implicit, which differs from Euler
// only in actuator and tendon terms, sim/core/simulation.h) takes the
// joints' damping C implicitly but the hinges' stiffness K and the fluid's
// drag D (the coupling's passive callback) explicitly. The Stokes step
// (plugin/dynamics/stokes_step.h) treats both implicitly and has no such
// limit.
//
// At the body's rest shape, with M the joint-space mass matrix (mj_fullM),
// D the drag's resistance (the fluid's force on unit joint velocities) and
// K and C diagonal:
//
//   drag relaxation   tau_D = 1 / lambda_max(M^-1 D); for one segment of
//                     mass m, normal drag coefficient xi_n and length L,
//                     m / (xi_n L)
//   hinge mode        omega_K = sqrt(lambda_max(M^-1 K)); one hinge of
//                     stiffness k and inertia I: sqrt(k / I)
//   response error    how far the step's response to a force at the
//                     wave's frequency is from the exact one, over the
//                     hinges: || H_h - H ||_F / || H ||_F with
//                     H = (K - w^2 M + i w (C + D))^-1 and H_h the same
//                     of Euler's map (v' = (M + h C)^-1 ((M - h D) v
//                     - h K q + h f), q' = q + h v'), both at w
//
// The swim is second order in the hinges' motion, and its error goes with
// the response error (measured in docs/RUNS.md, "The step's own error"),
// which sets kMaxResponseError.
#pragma once

#include <mujoco/mujoco.h>

#include <string>
#include <vector>

namespace ipmc {

// The largest response error and step per drag relaxation that keep the
// swim within 1 % of its step-converged value (docs/RUNS.md, "The step's
// own error"): the paper's run (0.5 ms, 0.01 Hz: response error 1.6e-5,
// h / tau 8.6e-4) is converged to 1.3e-4, the two-link strip of
// docs/OWN_ROBOT.md at 1 Hz is 1.4 % off at 10 us (response error 3.1e-5)
// in water and oil alike; the paper's strip in a 1 Pa s oil at 0.5 ms
// (h / tau 0.86) is 2e-4 from its swim at 0.125 ms, and explicit Euler
// on the drag alone is unstable beyond h / tau = 2.
constexpr double kMaxResponseError = 2e-5;
constexpr double kMaxStepPerDragRelaxation = 1.0;

struct StepResolution {
  bool explicit_drag = false;      // the run steps inertially (mj_step)
  double timestep_s = 0.0;
  double frequency_Hz = 0.0;       // the wave's
  double drag_relaxation_s = 0.0;  // tau_D; infinite without drag
  double hinge_rate_rad_s = 0.0;   // omega_K; 0: no stiffness
  double response_error = 0.0;     // at timestep_s
  // The largest timestep_s / 2^j whose response error is at most
  // kMaxResponseError (timestep_s itself if it is).
  double resolving_timestep_s = 0.0;
  bool Resolved() const;
};

// Measures m's relaxations and response error at d's positions for a wave
// of `frequency_Hz` (d itself is not changed). A model that steps with the
// Stokes step, or without a coupled fluid, or a run without a frequency,
// gives explicit_drag = false (and no warning).
StepResolution MeasureStepResolution(const mjModel* m, const mjData* d, double frequency_Hz);

// The warning for a step that does not resolve it (none if it does):
// names the step to use and dynamics = "stokes". `controller_rate_Hz` > 0
// rounds the step down to a whole number per controller sample.
std::vector<std::string> StepResolutionWarnings(const StepResolution& step,
                                                double controller_rate_Hz = 0.0);

}  // namespace ipmc
