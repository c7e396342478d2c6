#include "sim/runs/gait_run.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "ipmc_swim/ipmc_swim.h"
#include "sim/core/step_count.h"

namespace ipmc {
namespace {

struct Servo {
  int actuator;
  int joint;
  int qpos_adr;
  int dof_adr;
};

std::vector<Servo> FindServos(const mjModel* m) {
  std::vector<Servo> servos;
  for (int a = 0; a < m->nu; ++a) {
    const char* name = mj_id2name(m, mjOBJ_ACTUATOR, a);
    if (!name || std::string(name).rfind("servo_", 0) != 0) continue;
    const int joint = m->actuator_trnid[2 * a];
    servos.push_back({a, joint, m->jnt_qposadr[joint], m->jnt_dofadr[joint]});
  }
  return servos;
}

// The fluid's scale of the body's rotational drag about one end [N m s]
// (xi_n L^3 / 3 under RFT).
double RotationalDragScale(const mjData* d) {
  return IsAttached(d) ? FluidOf(d).rotational_drag_N_m_s : 0.0;
}

void SetServoGains(mjModel* m, const std::vector<Servo>& servos, double kp, double kv) {
  for (const Servo& servo : servos) {
    mjtNum* gain = m->actuator_gainprm + mjNGAIN * servo.actuator;
    mjtNum* bias = m->actuator_biasprm + mjNBIAS * servo.actuator;
    gain[0] = kp;
    bias[0] = 0.0;
    bias[1] = -kp;
    bias[2] = -kv;
  }
}

// ctrl such that kp ctrl - kp q - kv qd = kp (q_ref - q) + kv (qd_ref - qd)
// + k q_ref + c qd_ref.
void SetServoTargets(const mjModel* m, mjData* d, const std::vector<Servo>& servos,
                     const JointReference& ref, double kp, double kv) {
  // The damping the step takes (c_eff where the coupling gave it).
  const std::vector<double> damping =
      IsAttached(d) ? StepDamping(m, d) : std::vector<double>(m->dof_damping, m->dof_damping + m->nv);
  for (size_t j = 0; j < servos.size(); ++j) {
    const Servo& servo = servos[j];
    const double k = m->jnt_stiffness[servo.joint];
    const double c = damping[servo.dof_adr];
    const double q = ref.angle_rad[j], qd = ref.velocity_rad_s[j];
    d->ctrl[servo.actuator] = q + ((kv + c) * qd + k * q) / kp;
  }
}

double HingeInertiaMax(const mjModel* m, mjData* d, const std::vector<Servo>& servos) {
  mj_forward(m, d);
  double inertia = 0.0;
  for (const Servo& servo : servos) {
    inertia = std::max(inertia, d->qM[m->dof_Madr[servo.dof_adr]]);
  }
  return inertia;
}

GaitSample Sample(const SwimMeter& meter, const mjData* d, const std::vector<Servo>& servos,
                  const JointReference& ref) {
  GaitSample s;
  s.pose = meter.Pose(d);
  s.q_ref_rad = ref.angle_rad;
  for (const Servo& servo : servos) s.q_rad.push_back(d->qpos[servo.qpos_adr]);
  return s;
}

}  // namespace

void GaitRunOptions::Validate() const {
  if (cycles < 1) {
    throw FieldError("gait: cycles must be >= 1 (got " + std::to_string(cycles) + ")", "cycles",
                     ">= 1");
  }
  if (samples_per_cycle < 1) {
    throw FieldError("gait: samples_per_cycle must be >= 1 (got " +
                         std::to_string(samples_per_cycle) + ")",
                     "samples_per_cycle", ">= 1");
  }
  if (!(servo_time_constant_steps >= 2.0)) {
    throw FieldError("gait: servo_time_constant_steps must be >= 2 (got " +
                         FormatShortest(servo_time_constant_steps) + ")",
                     "servo_time_constant_steps", ">= 2");
  }
  if (!(servo_damping_over_drag > 0.0)) {
    throw FieldError("gait: servo_damping_over_drag must be > 0 (got " +
                         FormatShortest(servo_damping_over_drag) + ")",
                     "servo_damping_over_drag", "> 0");
  }
}

GaitRunResult RunGait(Simulation& sim, const Gait& gait, const GaitRunOptions& options) {
  options.Validate();
  mjModel* m = sim.model();
  mjData* d = sim.data();
  const std::vector<Servo> servos = FindServos(m);
  if (static_cast<int>(servos.size()) != gait.Joints()) {
    throw std::runtime_error(sim.source() + ": gait drives " + std::to_string(gait.Joints()) +
                             " joints but the model has " + std::to_string(servos.size()) +
                             " servo_* actuators");
  }
  SwimMeter meter(m);

  // Start at the gait's pose, root at rest.
  mj_resetData(m, d);
  const JointReference start = gait.At(0.0);
  for (size_t j = 0; j < servos.size(); ++j) {
    d->qpos[servos[j].qpos_adr] = start.angle_rad[j];
    d->qvel[servos[j].dof_adr] = start.velocity_rad_s[j];
  }
  const double dt = m->opt.timestep;
  const double servo_time_s = options.servo_time_constant_steps * dt;
  const double kv = std::max(
      options.servo_damping_over_drag * RotationalDragScale(d),
      4.0 * HingeInertiaMax(m, d, servos) / servo_time_s);
  const double kp = kv / servo_time_s;
  SetServoGains(m, servos, kp, kv);
  mj_forward(m, d);

  GaitRunResult result;
  result.gait = gait.Describe();
  result.period_s = gait.Period_s();
  result.timestep_s = dt;
  const long steps_per_cycle = CheckedStepCount(
      gait.Period_s(), dt, kMinSamplesPerWaveCycle,
      "gait: one cycle (the gait's period; at least " + std::to_string(kMinSamplesPerWaveCycle) +
          " steps)");
  const long sample_every =
      std::max<long>(1, steps_per_cycle / options.samples_per_cycle);
  CheckRunSize(static_cast<double>(options.cycles) * steps_per_cycle,
               static_cast<double>(options.cycles) * steps_per_cycle / sample_every *
                   RecordedSampleBytes(m->nq, static_cast<int>(servos.size())),
               options.allow_long, "gait: the run (--cycles x the gait's period)");
  const long settle_steps = steps_per_cycle / 20;

  // No step check (sim/core/step_resolution.h): the servos' gains, which
  // MuJoCo's implicit step takes implicitly, are not in its linear body.
  meter.Start(d);
  result.states = RecordedStates::For(m);
  result.samples.push_back(Sample(meter, d, servos, start));
  result.states.Record(d);
  for (int cycle = 0; cycle < options.cycles; ++cycle) {
    for (long step = 1; step <= steps_per_cycle; ++step) {
      // The servo aims at the reference at the end of the step.
      const double t_end = (cycle * steps_per_cycle + step) * dt;
      const JointReference ref = gait.At(t_end);
      SetServoTargets(m, d, servos, ref, kp, kv);
      sim.Step();
      d->time = t_end;  // avoid drift from summing dt
      if (cycle > 0 || step > settle_steps) {
        for (size_t j = 0; j < servos.size(); ++j) {
          const double error = std::abs(d->qpos[servos[j].qpos_adr] - ref.angle_rad[j]);
          result.max_tracking_error_rad = std::max(result.max_tracking_error_rad, error);
          result.max_reference_rad =
              std::max(result.max_reference_rad, std::abs(ref.angle_rad[j]));
        }
      }
      meter.Observe(m, d);
      if (step % sample_every == 0 || step == steps_per_cycle) {
        result.samples.push_back(Sample(meter, d, servos, ref));
        result.states.Record(d);
        if (options.on_sample) options.on_sample(d->time);
      }
    }
    meter.EndCycle(d);
  }
  result.swim = meter.Finish(d, 1, 0.0, 1.0 / gait.Period_s());
  RequireFiniteMetrics(result.swim, sim.source());
  return result;
}

}  // namespace ipmc
