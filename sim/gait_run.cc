#include "sim/gait_run.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "plugin/coupling.h"

namespace ipmc {
namespace {

constexpr double kMToMm = 1e3;

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

std::vector<int> FindTipSites(const mjModel* m) {
  std::vector<int> sites;
  for (int q = 1;; ++q) {
    const int id = mj_name2id(m, mjOBJ_SITE, ("tip" + std::to_string(q)).c_str());
    if (id < 0) break;
    sites.push_back(id);
  }
  return sites;
}

double RotationalDragScale(const CouplingContext* coupling, const mjModel* m, const mjData* d,
                           double* body_length_m) {
  *body_length_m = 0.0;
  if (!coupling || !coupling->drag) return 0.0;
  for (const Segment& s : coupling->drag->Segments(m, d)) *body_length_m += s.length_m;
  const double length = *body_length_m;
  return coupling->drag->coefficients().normal_N_s_m2 * length * length * length / 3.0;
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
  for (size_t j = 0; j < servos.size(); ++j) {
    const Servo& servo = servos[j];
    const double k = m->jnt_stiffness[servo.joint];
    const double c = m->dof_damping[servo.dof_adr];
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

GaitSample Sample(const mjData* d, const std::vector<Servo>& servos,
                  const std::vector<int>& tips, const JointReference& ref) {
  GaitSample s;
  s.t_s = d->time;
  const int root = 1;
  s.com_x_mm = d->subtree_com[3 * root] * kMToMm;
  s.com_y_mm = d->subtree_com[3 * root + 1] * kMToMm;
  s.head_x_mm = d->xpos[3 * root] * kMToMm;
  s.head_y_mm = d->xpos[3 * root + 1] * kMToMm;
  const mjtNum* xmat = d->xmat + 9 * root;
  s.yaw_rad = std::atan2(xmat[3], xmat[0]);
  s.q_ref_rad = ref.angle_rad;
  for (const Servo& servo : servos) s.q_rad.push_back(d->qpos[servo.qpos_adr]);
  for (int site : tips) {
    s.tip_x_mm.push_back(d->site_xpos[3 * site] * kMToMm);
    s.tip_y_mm.push_back(d->site_xpos[3 * site + 1] * kMToMm);
  }
  return s;
}

double LateralTipSpeed_m_s(const mjModel* m, const mjData* d, const std::vector<int>& tips) {
  if (tips.empty()) return 0.0;
  mjtNum velocity[6];
  mj_objectVelocity(m, d, mjOBJ_SITE, tips.back(), velocity, 0);
  return std::abs(velocity[4]);
}

}  // namespace

void GaitRunOptions::Validate() const {
  if (cycles < 1) throw std::invalid_argument("gait run: cycles must be >= 1");
  if (samples_per_cycle < 1) throw std::invalid_argument("gait run: samples_per_cycle must be >= 1");
  if (!(servo_time_constant_steps >= 2.0)) {
    throw std::invalid_argument("gait run: servo_time_constant_steps must be >= 2");
  }
  if (!(servo_damping_over_drag > 0.0)) {
    throw std::invalid_argument("gait run: servo_damping_over_drag must be > 0");
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
  const std::vector<int> tips = FindTipSites(m);
  const CouplingContext* coupling = FindCoupling(d);

  // Start at the gait's pose, root at rest.
  mj_resetData(m, d);
  const JointReference start = gait.At(0.0);
  for (size_t j = 0; j < servos.size(); ++j) {
    d->qpos[servos[j].qpos_adr] = start.angle_rad[j];
    d->qvel[servos[j].dof_adr] = start.velocity_rad_s[j];
  }
  double body_length_m = 0.0;
  const double dt = m->opt.timestep;
  const double servo_time_s = options.servo_time_constant_steps * dt;
  const double kv = std::max(
      options.servo_damping_over_drag * RotationalDragScale(coupling, m, d, &body_length_m),
      4.0 * HingeInertiaMax(m, d, servos) / servo_time_s);
  const double kp = kv / servo_time_s;
  SetServoGains(m, servos, kp, kv);
  mj_forward(m, d);

  GaitRunResult result;
  result.gait = gait.Describe();
  result.period_s = gait.Period_s();
  result.timestep_s = dt;
  result.body_length_mm = body_length_m * kMToMm;
  const long steps_per_cycle = std::lround(gait.Period_s() / dt);
  const long sample_every =
      std::max<long>(1, steps_per_cycle / options.samples_per_cycle);
  const long settle_steps = steps_per_cycle / 20;

  GaitSample cycle_start = Sample(d, servos, tips, start);
  result.samples.push_back(cycle_start);
  const GaitSample run_start = cycle_start;
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
      result.peak_lateral_tip_speed_mm_s = std::max(result.peak_lateral_tip_speed_mm_s,
                                                    LateralTipSpeed_m_s(m, d, tips) * kMToMm);
      if (step % sample_every == 0 || step == steps_per_cycle) {
        result.samples.push_back(Sample(d, servos, tips, ref));
      }
    }
    const GaitSample& end = result.samples.back();
    result.per_cycle.push_back({-(end.com_x_mm - cycle_start.com_x_mm),
                                end.com_y_mm - cycle_start.com_y_mm,
                                -(end.head_x_mm - cycle_start.head_x_mm),
                                end.head_y_mm - cycle_start.head_y_mm});
    cycle_start = end;
  }
  const GaitSample& end = result.samples.back();
  result.mean_speed_along_mm_s = -(end.com_x_mm - run_start.com_x_mm) / end.t_s;

  if (coupling && coupling->drag) {
    const RftDragConfig& fluid = coupling->drag->config();
    const int width_id = mj_name2id(m, mjOBJ_NUMERIC, "ipmc_strip_width_m");
    const double width_m = width_id >= 0 ? m->numeric_data[m->numeric_adr[width_id]]
                                         : 2.0 * fluid.equivalent_radius_m;
    const double rho_over_mu = fluid.fluid_density_kg_m3 / fluid.viscosity_Pa_s;
    result.reynolds_tip = rho_over_mu * result.peak_lateral_tip_speed_mm_s / kMToMm * width_m;
    result.reynolds_swim =
        rho_over_mu * std::abs(result.mean_speed_along_mm_s) / kMToMm * body_length_m;
  }
  return result;
}

}  // namespace ipmc
