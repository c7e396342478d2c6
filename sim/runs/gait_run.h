// Kinematic mode: the driven hinges follow a prescribed gait through
// stiff servos while the root (and any undriven hinge) moves under the
// drag. Measures the net displacement per cycle.
//
// Servo (the model's "servo_*" general actuators, affine bias):
//   tau = kp (q_ref - q) + kv (qd_ref - qd) + k q_ref + c qd_ref
// with the hinge's own stiffness k and damping c fed forward. kv is the
// larger of 100 times the body's rotational drag xi_n L^3 / 3 and
// 4 J / T_s (J the largest hinge inertia), kp = kv / T_s, T_s = 10 dt:
// an overdamped servo ten steps fast whose damping MuJoCo's implicit
// integrator treats implicitly. Swim metrics and frames: sim/core/swim_meter.h.
#pragma once

#include <string>
#include <vector>

#include "sim/core/gait.h"
#include "sim/core/simulation.h"
#include "sim/core/swim_meter.h"
#include "sim/runs/recorded_states.h"

namespace ipmc {

struct GaitRunOptions {
  int cycles = 3;
  int samples_per_cycle = 200;
  double servo_time_constant_steps = 10.0;
  double servo_damping_over_drag = 100.0;
  void Validate() const;
};

struct GaitSample {
  BodyPose pose;
  std::vector<double> q_ref_rad, q_rad;
};

struct GaitRunResult {
  std::string gait;
  double period_s = 0.0;
  double timestep_s = 0.0;
  SwimMetrics swim;
  double max_tracking_error_rad = 0.0;    // after the first 5 % of cycle 1
  double max_reference_rad = 0.0;
  std::vector<GaitSample> samples;
  RecordedStates states;  // the model's qpos at every sample
};

// Runs `options.cycles` periods of `gait` on sim (whose model must carry
// one servo_* actuator per gait joint). Starts from the gait's pose at
// t = 0 with the root at rest. Throws std::runtime_error on mismatch or
// divergence.
GaitRunResult RunGait(Simulation& sim, const Gait& gait, const GaitRunOptions& options);

}  // namespace ipmc
