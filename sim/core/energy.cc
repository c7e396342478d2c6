#include "sim/core/energy.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ipmc_swim/ipmc_swim.h"

namespace ipmc {
namespace {

constexpr double kMmToM = 1e-3;

// The cycles' mean powers over cycles [from, end) (0-based).
EnergyPowers MeanPowers(const std::vector<EnergyCycle>& cycles, size_t from, size_t links) {
  EnergyPowers mean;
  mean.actuator_power_W.assign(links, 0.0);
  const double n = static_cast<double>(cycles.size() - from);
  if (!(n > 0)) return mean;
  for (size_t k = from; k < cycles.size(); ++k) {
    const EnergyCycle& c = cycles[k];
    for (size_t q = 0; q < links; ++q) mean.actuator_power_W[q] += c.actuator_power_W[q] / n;
    mean.actuator_power_W_total += c.actuator_power_W_total / n;
    mean.fluid_power_W += c.fluid_power_W / n;
    mean.hinge_damping_power_W += c.hinge_damping_power_W / n;
    mean.stepping_power_W += c.stepping_power_W / n;
    mean.electrical_power_W.resize(c.electrical_power_W.size(), 0.0);
    for (size_t q = 0; q < c.electrical_power_W.size(); ++q) {
      mean.electrical_power_W[q] += c.electrical_power_W[q] / n;
    }
    mean.electrical_power_W_total += c.electrical_power_W_total / n;
  }
  return mean;
}

// eta = D_tow(U) U / P_f and P / |U|, 0 where undefined (no drag, no
// fluid power); the cost of transport is infinite for a body that does not
// swim.
double LighthillEfficiency(double towing_drag_N, double speed_m_s, double fluid_power_W) {
  return fluid_power_W > 0 ? towing_drag_N * speed_m_s / fluid_power_W : 0.0;
}
double CostOfTransport_J_m(double power_W, double speed_m_s) {
  return speed_m_s != 0 ? power_W / std::abs(speed_m_s)
                        : std::numeric_limits<double>::infinity();
}
// Mechanical over electrical power, 0 without electrical power.
double ElectromechanicalEfficiency(const EnergyPowers& p) {
  return p.electrical_power_W_total > 0 ? p.actuator_power_W_total / p.electrical_power_W_total
                                        : 0.0;
}

}  // namespace

EnergyMeter::EnergyMeter(const mjModel* m, const mjData* d) : attached_(IsAttached(d)) {
  for (int q = 0; attached_ && q < LinkCount(d); ++q) {
    std::vector<int> dofs;
    for (int joint : LinkJoints(d, q)) dofs.push_back(m->jnt_dofadr[joint]);
    link_dofs_.push_back(dofs);
  }
  if (attached_) {
    const FluidFacts fluid = FluidOf(d);
    drag_ = fluid.drag;
    towing_drag_N_per_m_s_ = fluid.towing_drag_N_s_m;
  }
  inertial_ = !attached_ || !StokesDynamics(d);
  // MuJoCo's Euler and implicit steps take the damping implicitly.
  implicit_damping_ =
      inertial_ && (m->opt.integrator == mjINT_EULER || m->opt.integrator == mjINT_IMPLICIT);
  first_order_hold_ = implicit_damping_ && !link_dofs_.empty() && LinkMomentHold(d, 0).first_order;
  // The damping the step takes (c_eff where the coupling gave it).
  step_damping_ = attached_ ? StepDamping(m, d)
                            : std::vector<double>(m->dof_damping, m->dof_damping + m->nv);
  if (first_order_hold_) physical_damping_.assign(m->dof_damping, m->dof_damping + m->nv);
  step_start_velocity_.assign(d->qvel, d->qvel + m->nv);
  actuator_J_.assign(link_dofs_.size(), 0.0);
  scratch_.assign(m->nv, 0.0);
  step_start_moment_N_m_.assign(d->qfrc_actuator, d->qfrc_actuator + m->nv);
  cycle_start_stored_J_ = StoredEnergy_J(m, d);
}

void EnergyMeter::MeasureElectrical(const ElectricalConfig& config,
                                    const std::vector<double>& link_lengths_mm) {
  impedances_.clear();
  electrical_J_.clear();
  if (!config.enabled) return;
  config.Validate();
  for (size_t q = 0; q < link_dofs_.size() && q < link_lengths_mm.size(); ++q) {
    const double area_m2 = link_lengths_mm[q] * kMmToM * config.electrode_width_mm * kMmToM;
    impedances_.push_back(IpmcImpedance::ForArea(config, area_m2));
  }
  electrical_J_.assign(impedances_.size(), 0.0);
}

double EnergyMeter::ElasticEnergy_J(const mjModel* m, const mjData* d) {
  double energy_J = 0.0;
  for (int j = 0; j < m->njnt; ++j) {
    const int type = m->jnt_type[j];
    if (type != mjJNT_HINGE && type != mjJNT_SLIDE) continue;
    const double strain = d->qpos[m->jnt_qposadr[j]] - m->qpos_spring[m->jnt_qposadr[j]];
    energy_J += 0.5 * m->jnt_stiffness[j] * strain * strain;
  }
  return energy_J;
}

double EnergyMeter::StoredEnergy_J(const mjModel* m, const mjData* d) {
  double energy_J = ElasticEnergy_J(m, d);
  if (inertial_) {
    mj_mulM(m, d, scratch_.data(), d->qvel);
    energy_J += 0.5 * mju_dot(d->qvel, scratch_.data(), m->nv);
  }
  return energy_J;
}

double EnergyMeter::KineticStepError_J(const mjModel* m, const mjData* d) {
  std::vector<double>& change = step_start_velocity_;  // becomes v_(n+1) - v_n
  for (int dof = 0; dof < m->nv; ++dof) change[dof] = d->qvel[dof] - change[dof];
  mj_mulM(m, d, scratch_.data(), change.data());  // M of the step's start, which it solved with
  const double error_J = 0.5 * mju_dot(change.data(), scratch_.data(), m->nv);
  change.assign(d->qvel, d->qvel + m->nv);
  return error_J;
}

double EnergyMeter::FirstOrderHoldStep(const mjModel* m, const mjData* d) {
  const double h = m->opt.timestep;
  // The held moment's excess over the trapezoid, (w - 1/2) (f_(n+1) - f_n),
  // times the joint rate [W].
  double held_excess_W = 0.0;
  for (size_t q = 0; q < link_dofs_.size(); ++q) {
    const MomentHold hold = LinkMomentHold(d, static_cast<int>(q));
    double power_W = 0.0;
    for (size_t i = 0; i < link_dofs_[q].size() && !hold.end_N_m.empty(); ++i) {
      const int dof = link_dofs_[q][i];
      const double mean_N_m = 0.5 * (hold.start_N_m[i] + hold.end_N_m[i]);
      power_W += mean_N_m * d->qvel[dof];
      held_excess_W += (d->qfrc_actuator[dof] - mean_N_m) * d->qvel[dof];
    }
    actuator_J_[q] += h * power_W;
  }
  // Every dof: c qdot^2 booked as damping, (c_eff - c - k h / 2) qdot^2
  // of what the step dissipates left to the stepping term.
  double damping_W = 0.0, excess_damping_W = 0.0;
  for (int dof = 0; dof < m->nv; ++dof) {
    const double rate2 = d->qvel[dof] * d->qvel[dof];
    damping_W += physical_damping_[dof] * rate2;
    excess_damping_W += (step_damping_[dof] - physical_damping_[dof]) * rate2;
  }
  for (int j = 0; j < m->njnt; ++j) {
    const int type = m->jnt_type[j];
    if (type != mjJNT_HINGE && type != mjJNT_SLIDE) continue;
    const double rate = d->qvel[m->jnt_dofadr[j]];
    excess_damping_W -= 0.5 * m->jnt_stiffness[j] * h * rate * rate;
  }
  damping_J_ += h * damping_W;
  return h * (excess_damping_W - held_excess_W) + KineticStepError_J(m, d);
}

void EnergyMeter::Observe(const mjModel* m, const mjData* d) {
  const double h = m->opt.timestep;
  if (first_order_hold_) {
    stepping_J_ += FirstOrderHoldStep(m, d);
    ObserveFluidAndElectrical(m, d);
    return;
  }
  // Stokes: the trapezoid of the active moments over the step, whose
  // change v . (f_end - f_start) h / 2 the backward-Euler balance leaves
  // to the stepping term.
  double moment_change_W = 0.0;
  for (size_t q = 0; q < link_dofs_.size(); ++q) {
    double power_W = 0.0;
    for (int dof : link_dofs_[q]) {
      const double end_N_m = d->qfrc_actuator[dof];
      double& start_N_m = step_start_moment_N_m_[dof];
      const double mean_N_m = inertial_ ? end_N_m : 0.5 * (start_N_m + end_N_m);
      power_W += mean_N_m * d->qvel[dof];
      if (!inertial_) moment_change_W += 0.5 * (end_N_m - start_N_m) * d->qvel[dof];
      start_N_m = end_N_m;
    }
    actuator_J_[q] += h * power_W;
  }
  double damping_W = 0.0;
  for (int dof = 0; dof < m->nv; ++dof) damping_W += step_damping_[dof] * d->qvel[dof] * d->qvel[dof];
  double spring_h_W = 0.0;  // sum of k h qdot^2 / 2 over the joints
  for (int j = 0; j < m->njnt; ++j) {
    const int type = m->jnt_type[j];
    if (type != mjJNT_HINGE && type != mjJNT_SLIDE) continue;
    const double rate = d->qvel[m->jnt_dofadr[j]];
    spring_h_W += 0.5 * m->jnt_stiffness[j] * h * rate * rate;
  }
  if (!inertial_) {
    damping_J_ += h * damping_W;
    stepping_J_ += h * (spring_h_W - moment_change_W);
  } else if (implicit_damping_) {
    // (c_eff - k h / 2) qdot^2 per joint (plugin/dynamics/step_model.h).
    damping_J_ += h * (damping_W - spring_h_W);
    stepping_J_ += KineticStepError_J(m, d);
  } else {
    damping_J_ += h * damping_W;
    stepping_J_ -= h * spring_h_W;
  }
  ObserveFluidAndElectrical(m, d);
}

void EnergyMeter::ObserveFluidAndElectrical(const mjModel* m, const mjData* d) {
  const double h = m->opt.timestep;
  if (drag_) fluid_J_ += h * StepFluidPower_W(m, d);
  elastic_J_s_ += h * ElasticEnergy_J(m, d);
  // The voltage set before the step was held over it.
  for (size_t q = 0; q < impedances_.size(); ++q) {
    electrical_J_[q] += impedances_[q].Hold(LinkVoltage_V(d, static_cast<int>(q)), h).input_J;
  }
  time_s_ += h;
}

void EnergyMeter::EndCycle(const mjModel* m, const mjData* d) {
  EnergyCycle cycle;
  const double duration_s = time_s_ > 0 ? time_s_ : 1.0;
  for (double& energy_J : actuator_J_) {
    cycle.actuator_power_W.push_back(energy_J / duration_s);
    cycle.actuator_power_W_total += energy_J / duration_s;
    energy_J = 0.0;
  }
  for (double& energy_J : electrical_J_) {
    cycle.electrical_power_W.push_back(energy_J / duration_s);
    cycle.electrical_power_W_total += energy_J / duration_s;
    energy_J = 0.0;
  }
  cycle.electromechanical_efficiency = ElectromechanicalEfficiency(cycle);
  cycle.fluid_power_W = fluid_J_ / duration_s;
  cycle.hinge_damping_power_W = damping_J_ / duration_s;
  cycle.stepping_power_W = stepping_J_ / duration_s;
  cycle.elastic_energy_J = elastic_J_s_ / duration_s;
  const double stored_J = StoredEnergy_J(m, d);
  cycle.stored_energy_change_J = stored_J - cycle_start_stored_J_;
  cycle_start_stored_J_ = stored_J;
  fluid_J_ = damping_J_ = stepping_J_ = elastic_J_s_ = time_s_ = 0.0;
  cycles_.push_back(cycle);
}

EnergyMetrics EnergyMeter::Finish(const SwimMetrics& swim, double period_s, int from_cycle) const {
  EnergyMetrics metrics;
  metrics.per_cycle = cycles_;
  for (size_t k = 0; k < metrics.per_cycle.size() && k < swim.per_cycle.size(); ++k) {
    EnergyCycle& c = metrics.per_cycle[k];
    const double speed_m_s = swim.per_cycle[k].com_along * kMmToM / period_s;
    c.lighthill_efficiency =
        LighthillEfficiency(towing_drag_N_per_m_s_ * speed_m_s, speed_m_s, c.fluid_power_W);
    c.cost_of_transport_J_m = CostOfTransport_J_m(c.actuator_power_W_total, speed_m_s);
  }
  metrics.from_cycle = from_cycle;
  const size_t from = static_cast<size_t>(std::max(1, from_cycle) - 1);
  static_cast<EnergyPowers&>(metrics) = MeanPowers(cycles_, from, link_dofs_.size());
  const double n = static_cast<double>(cycles_.size() > from ? cycles_.size() - from : 0);
  for (size_t k = from; k < cycles_.size(); ++k) metrics.elastic_energy_J += cycles_[k].elastic_energy_J / n;
  const double speed_m_s = swim.mean_speed_along_mm_s * kMmToM;
  metrics.towing_drag_N = towing_drag_N_per_m_s_ * speed_m_s;
  metrics.lighthill_efficiency =
      LighthillEfficiency(metrics.towing_drag_N, speed_m_s, metrics.fluid_power_W);
  metrics.cost_of_transport_J_m = CostOfTransport_J_m(metrics.actuator_power_W_total, speed_m_s);
  metrics.electrical = !impedances_.empty();
  metrics.electromechanical_efficiency = ElectromechanicalEfficiency(metrics);
  return metrics;
}

}  // namespace ipmc
