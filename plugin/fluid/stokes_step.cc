#include "plugin/fluid/stokes_step.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace ipmc {
namespace {

std::string Name(const mjModel* m, mjtObj type, int id) {
  const char* name = mj_id2name(m, type, id);
  return name ? std::string("'") + name + "'" : "#" + std::to_string(id);
}

void RequireSupported(const mjModel* m) {
  const std::string prefix = "dynamics = stokes: ";
  if (!(m->opt.disableflags & mjDSBL_CONTACT) && m->ngeom > 0) {
    throw std::invalid_argument(prefix +
                                "contacts are not supported (the model needs <flag "
                                "contact=\"disable\"/> in <option>)");
  }
  if (m->neq > 0) throw std::invalid_argument(prefix + "equality constraints are not supported");
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_limited[j]) {
      throw std::invalid_argument(prefix + "joint " + Name(m, mjOBJ_JOINT, j) +
                                  " is limited; joint limits are not supported");
    }
  }
  for (int t = 0; t < m->ntendon; ++t) {
    if (m->tendon_limited[t]) {
      throw std::invalid_argument(prefix + "tendon " + Name(m, mjOBJ_TENDON, t) +
                                  " is limited; tendon limits are not supported");
    }
  }
  if (m->na > 0) {
    throw std::invalid_argument(prefix + "actuators with activation dynamics are not supported");
  }
}

// h K + C of each dof: the joints' stiffness and damping, and an affine
// actuator's dependence on its joint's position and velocity (a servo's
// bias -kp q - kv qdot), force = gain(ctrl) + b0 + b1 l + b2 ldot with
// l = g q on a joint transmission.
void ImplicitDiagonal(const mjModel* m, const mjData* d, double h, double* diagonal) {
  for (int dof = 0; dof < m->nv; ++dof) {
    diagonal[dof] = m->dof_damping[dof];
    const int joint = m->dof_jntid[dof];
    const int type = m->jnt_type[joint];
    if (type == mjJNT_HINGE || type == mjJNT_SLIDE) diagonal[dof] += h * m->jnt_stiffness[joint];
  }
  for (int a = 0; a < m->nu; ++a) {
    if (m->actuator_trntype[a] != mjTRN_JOINT) continue;
    const int joint = m->actuator_trnid[2 * a];
    const int type = m->jnt_type[joint];
    if (type != mjJNT_HINGE && type != mjJNT_SLIDE) continue;
    const double gear = m->actuator_gear[6 * a];
    double d_length = 0, d_velocity = 0;  // dforce/dl, dforce/dldot
    if (m->actuator_biastype[a] == mjBIAS_AFFINE) {
      d_length += m->actuator_biasprm[mjNBIAS * a + 1];
      d_velocity += m->actuator_biasprm[mjNBIAS * a + 2];
    }
    if (m->actuator_gaintype[a] == mjGAIN_AFFINE) {
      d_length += m->actuator_gainprm[mjNGAIN * a + 1] * d->ctrl[a];
      d_velocity += m->actuator_gainprm[mjNGAIN * a + 2] * d->ctrl[a];
    }
    diagonal[m->jnt_dofadr[joint]] -= gear * gear * (h * d_length + d_velocity);
  }
}

}  // namespace

bool JointActuatorsOnly(const mjModel* m) {
  for (int a = 0; a < m->nu; ++a) {
    if (m->actuator_trntype[a] != mjTRN_JOINT || m->actuator_dyntype[a] != mjDYN_NONE) return false;
    const int type = m->jnt_type[m->actuator_trnid[2 * a]];
    if (type != mjJNT_HINGE && type != mjJNT_SLIDE) return false;
    const int gain = m->actuator_gaintype[a], bias = m->actuator_biastype[a];
    if (gain != mjGAIN_FIXED && gain != mjGAIN_AFFINE) return false;
    if (bias != mjBIAS_NONE && bias != mjBIAS_AFFINE) return false;
  }
  return true;
}

StokesStepper::StokesStepper(const mjModel* m) {
  RequireSupported(m);
  joint_actuators_only_ = JointActuatorsOnly(m);
  body_node_.assign(m->nbody, -1);
  for (int body = 1; body < m->nbody; ++body) {
    body_node_[body] = m->body_dofnum[body] > 0
                           ? m->body_dofadr[body] + m->body_dofnum[body] - 1
                           : body_node_[m->body_parentid[body]];
  }
  articulated_.resize(m->nv);
  bias_.resize(m->nv);
  u_vector_.resize(m->nv);
  velocity_.resize(m->nv);
  u_.resize(m->nv);
  pivot_.resize(m->nv);
  diagonal_.resize(m->nv);
  force_.resize(m->nv);
  cdof_.resize(6 * m->nv);
  last_cdof_.resize(6 * m->nv);
  midpoint_cdof_.resize(6 * m->nv);
  end_qpos_.resize(m->nq);
}

// The fluid's resistance D = sum_s J_s^T S_s J_s enters the step here, and
// only here: each segment's spatial resistance S_s at the step's midpoint
// (ExtrapolateToMidpoint, from RftDrag::Resistances, the formula the drag
// callback applies) added to the articulated resistance of its body's last
// dof, from which Solve's recursion carries it to the root.
void StokesStepper::AssembleResistances(const mjModel* m) {
  for (int j = 0; j < m->nv; ++j) articulated_[j].setZero();
  for (const RftDrag::BodyResistance& segment : midpoint_resistances_) {
    const int node = body_node_[segment.body];
    if (node >= 0) articulated_[node] += segment.resistance;
  }
}

// Minimising 1/2 sum_b V_b^T S_b V_b + 1/2 sum_j e_j v_j^2 - f^T v over v,
// where a dof's spatial velocity is its parent dof's plus s_j v_j
// (s_j = cdof_j), dof by dof from the leaves: the subtree below dof j costs
// 1/2 V^T A_j V + p_j^T V at its velocity V, and eliminating v_j gives its
// parent A += A_j - U U^T / D_j, p += p_j + U u_j / D_j with U = A_j s_j,
// D_j = s_j.U + e_j, u_j = f_j - s_j.p_j; then, from the root,
// v_j = (u_j - U.V_parent) / D_j.
bool StokesStepper::Solve(const mjModel* m, const double* cdof, const double* extra,
                          const double* f, double* v) {
  const int nv = m->nv;
  for (int j = 0; j < nv; ++j) bias_[j].setZero();
  for (int j = nv - 1; j >= 0; --j) {
    const Eigen::Map<const Vector6> s(cdof + 6 * j);
    u_vector_[j].noalias() = articulated_[j] * s;
    pivot_[j] = s.dot(u_vector_[j]) + extra[j];
    if (!(pivot_[j] > 0)) return false;
    u_[j] = f[j] - s.dot(bias_[j]);
    const int parent = m->dof_parentid[j];
    if (parent < 0) continue;
    articulated_[parent] += articulated_[j];
    articulated_[parent].noalias() -= u_vector_[j] * (u_vector_[j].transpose() / pivot_[j]);
    bias_[parent] += bias_[j] + u_vector_[j] * (u_[j] / pivot_[j]);
  }
  for (int j = 0; j < nv; ++j) {
    const Eigen::Map<const Vector6> s(cdof + 6 * j);
    const int parent = m->dof_parentid[j];
    const Vector6 parent_velocity = parent < 0 ? Vector6::Zero() : velocity_[parent];
    v[j] = (u_[j] - u_vector_[j].dot(parent_velocity)) / pivot_[j];
    velocity_[j] = parent_velocity + s * v[j];
  }
  return true;
}

// D = J^T R J + diag(extra), J (6 bodies x nv) the bodies' dof motions
// (their chains' cdof at the midpoint), solved densely.
bool StokesStepper::SolveDense(const mjModel* m, const FluidModel& fluid, const double* extra,
                               const double* f, double* v) {
  const int nv = m->nv;
  const std::vector<int>& bodies = fluid.bodies();
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(6 * bodies.size(), nv);
  for (size_t i = 0; i < bodies.size(); ++i) {
    for (int j = body_node_[bodies[i]]; j >= 0; j = m->dof_parentid[j]) {
      jacobian.block(6 * i, j, 6, 1) = Eigen::Map<const Vector6>(midpoint_cdof_.data() + 6 * j);
    }
  }
  Eigen::MatrixXd system = jacobian.transpose() * midpoint_dense_ * jacobian;
  for (int j = 0; j < nv; ++j) system(j, j) += extra[j];
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(system);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) return false;
  Eigen::Map<Eigen::VectorXd>(v, nv) = ldlt.solve(Eigen::Map<const Eigen::VectorXd>(f, nv));
  return true;
}

bool StokesStepper::Step(const mjModel* m, mjData* d, const FluidModel* fluid) {
  const double h = m->opt.timestep;
  const bool sensors = !(m->opt.disableflags & mjDSBL_SENSOR);
  // Position stage without the mass matrix (mj_fwdPosition less mj_crb,
  // mj_factorM and the constraints).
  mj_kinematics(m, d);
  mj_comPos(m, d);
  mj_camlight(m, d);
  mj_tendon(m, d);
  Transmission(m, d);
  if (sensors) mj_sensorPos(m, d);
  ExtrapolateToMidpoint(m, d, fluid);
  AssembleResistances(m);
  // The forces at zero velocity, in mj_forward's order: passive (springs;
  // the drag vanishes), control callback, actuation.
  mju_zero(d->qvel, m->nv);
  mju_zero(d->actuator_velocity, m->nu);
  mju_zero(d->ten_velocity, m->ntendon);
  mju_zero(d->cvel, 6 * m->nbody);
  mj_passive(m, d);
  // The active moments at the step's end, t_n + h (backward Euler in them
  // too): the control callback advances the actuators to d->time.
  if (mjcb_control) {
    const double start_s = d->time;
    d->time = start_s + h;
    mjcb_control(m, d);
    d->time = start_s;
  }
  Actuation(m, d);
  for (int j = 0; j < m->nv; ++j) {
    force_[j] = d->qfrc_passive[j] + d->qfrc_actuator[j] + d->qfrc_applied[j];
  }
  ImplicitDiagonal(m, d, h, diagonal_.data());
  const bool solved =
      fluid && fluid->nonlocal()
          ? SolveDense(m, *fluid, diagonal_.data(), force_.data(), d->qvel)
          : Solve(m, midpoint_cdof_.data(), diagonal_.data(), force_.data(), d->qvel);
  if (!solved) return false;
  mju_zero(d->qacc, m->nv);
  mj_comVel(m, d);
  if (sensors) mj_sensorVel(m, d);
  mj_integratePos(m, d->qpos, d->qvel, h);
  d->time += h;
  mju_copy(end_qpos_.data(), d->qpos, m->nq);
  end_time_ = d->time;
  return true;
}

void StokesStepper::Transmission(const mjModel* m, mjData* d) {
  if (!joint_actuators_only_ || !moments_set_) {
    mj_transmission(m, d);
    moments_set_ = true;
    return;
  }
  JointTransmission(m, d);
}

void StokesStepper::Actuation(const mjModel* m, mjData* d) {
  if (joint_actuators_only_) {
    JointActuation(m, d);
  } else {
    mj_fwdActuation(m, d);
  }
}

void JointTransmission(const mjModel* m, mjData* d) {
  for (int a = 0; a < m->nu; ++a) {
    const int joint = m->actuator_trnid[2 * a];
    const double gear = m->actuator_gear[6 * a];
    d->actuator_length[a] = gear * d->qpos[m->jnt_qposadr[joint]];
    d->actuator_moment[a * m->nv + m->jnt_dofadr[joint]] = gear;
  }
}

// MuJoCo 2.2's mj_fwdActuation (engine_forward.c) less its dense
// moment^T force: the same clamped controls, gains, biases and force
// limits, the generalised force summed in the same actuator order.
void JointActuation(const mjModel* m, mjData* d) {
  bool plain = !(m->opt.disableflags & mjDSBL_ACTUATION);
  for (int a = 0; plain && a < m->nu; ++a) plain = !mju_isBad(d->ctrl[a]);
  if (!plain) {
    mj_fwdActuation(m, d);
    return;
  }
  const bool clamp = !(m->opt.disableflags & mjDSBL_CLAMPCTRL);
  mju_zero(d->qfrc_actuator, m->nv);
  for (int a = 0; a < m->nu; ++a) {
    double ctrl = d->ctrl[a];
    if (clamp && m->actuator_ctrllimited[a]) {
      ctrl = mju_clip(ctrl, m->actuator_ctrlrange[2 * a], m->actuator_ctrlrange[2 * a + 1]);
    }
    const double length = d->actuator_length[a], velocity = d->actuator_velocity[a];
    const mjtNum* gain_prm = m->actuator_gainprm + mjNGAIN * a;
    double gain = gain_prm[0];
    if (m->actuator_gaintype[a] == mjGAIN_AFFINE) {
      gain = gain_prm[0] + gain_prm[1] * length + gain_prm[2] * velocity;
    }
    double force = gain * ctrl;
    if (m->actuator_biastype[a] == mjBIAS_AFFINE) {
      const mjtNum* bias_prm = m->actuator_biasprm + mjNBIAS * a;
      force += bias_prm[0] + bias_prm[1] * length + bias_prm[2] * velocity;
    }
    if (m->actuator_forcelimited[a]) {
      force = mju_clip(force, m->actuator_forcerange[2 * a], m->actuator_forcerange[2 * a + 1]);
    }
    d->actuator_force[a] = force;
    if (force != 0) {
      d->qfrc_actuator[m->jnt_dofadr[m->actuator_trnid[2 * a]]] += m->actuator_gear[6 * a] * force;
    }
  }
}

// The midpoint's S and cdof, 3/2 of this step's minus 1/2 of the last
// one's (second order), if d continues the last step; this step's
// otherwise (the first step, or after a reset or rewind).
void StokesStepper::ExtrapolateToMidpoint(const mjModel* m, const mjData* d,
                                          const FluidModel* fluid) {
  const bool continues = have_last_ && d->time == end_time_ &&
                         std::equal(end_qpos_.begin(), end_qpos_.end(), d->qpos);
  last_resistances_.swap(resistances_);
  resistances_.clear();
  if (fluid && fluid->nonlocal()) {
    last_dense_.swap(dense_);
    dense_ = fluid->BodyResistance(m, d);
    midpoint_dense_ = continues && last_dense_.rows() == dense_.rows()
                          ? (1.5 * dense_ - 0.5 * last_dense_).eval()
                          : dense_;
  } else if (fluid) {
    fluid->LocalResistances(m, d, &resistances_);
  }
  last_cdof_.swap(cdof_);
  mju_copy(cdof_.data(), d->cdof, 6 * m->nv);
  have_last_ = true;
  if (!continues || last_resistances_.size() != resistances_.size()) {
    midpoint_resistances_ = resistances_;
    midpoint_cdof_ = cdof_;
    return;
  }
  midpoint_resistances_.resize(resistances_.size());
  for (size_t i = 0; i < resistances_.size(); ++i) {
    midpoint_resistances_[i].body = resistances_[i].body;
    midpoint_resistances_[i].resistance =
        1.5 * resistances_[i].resistance - 0.5 * last_resistances_[i].resistance;
  }
  for (size_t i = 0; i < cdof_.size(); ++i) midpoint_cdof_[i] = 1.5 * cdof_[i] - 0.5 * last_cdof_[i];
}

}  // namespace ipmc
