#include "plugin/dynamics/stokes_step.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "plugin/mjcf/spatial_algebra.h"

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
void StiffnessAndDamping(const mjModel* m, const mjData* d, double h, double* diagonal) {
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

// True if every dof's motion (cdof = [w; v]) has w_x = w_y = v_z = 0:
// the body moves in the x-y plane.
bool PlanarMotions(const double* cdof, int nv) {
  for (int j = 0; j < nv; ++j) {
    const double* s = cdof + 6 * j;
    if (s[0] != 0 || s[1] != 0 || s[5] != 0) return false;
  }
  return true;
}

}  // namespace

bool HingesAndSlidesOnly(const mjModel* m) {
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE) return false;
  }
  return true;
}

// mj_comPos (MuJoCo 2.2, engine_core_smooth.c) less the bodies' inertias
// in the centre-of-mass frames: subtree_com by the same backward pass,
// then cdof = [axis; axis x (c - anchor)] of a hinge and [0; axis] of a
// slide about its root's centre of mass c.
void StokesComPos(const mjModel* m, mjData* d) {
  // MuJoCo's mju_addToScl3, mju_addTo3, mju_scl3, mju_sub3 and mju_cross
  // written out (the same operations in the same order, without a call
  // per body: this runs at every step).
  mjtNum* com = d->subtree_com;
  for (int k = 0; k < 3 * m->nbody; ++k) com[k] = 0;
  for (int i = m->nbody - 1; i >= 0; --i) {
    mjtNum* c = com + 3 * i;
    const mjtNum* xipos = d->xipos + 3 * i;
    const mjtNum mass = m->body_mass[i];
    for (int k = 0; k < 3; ++k) c[k] += xipos[k] * mass;
    if (i) {
      mjtNum* parent = com + 3 * m->body_parentid[i];
      for (int k = 0; k < 3; ++k) parent[k] += c[k];
    }
    if (m->body_subtreemass[i] < mjMINVAL) {
      for (int k = 0; k < 3; ++k) c[k] = xipos[k];
    } else {
      const mjtNum scale = 1.0 / m->body_subtreemass[i];
      for (int k = 0; k < 3; ++k) c[k] *= scale;
    }
  }
  for (int j = 0; j < m->njnt; ++j) {
    mjtNum* cdof = d->cdof + 6 * m->jnt_dofadr[j];
    const mjtNum* axis = d->xaxis + 3 * j;
    if (m->jnt_type[j] == mjJNT_SLIDE) {
      for (int k = 0; k < 3; ++k) {
        cdof[k] = 0;
        cdof[3 + k] = axis[k];
      }
      continue;
    }
    const mjtNum* c = com + 3 * m->body_rootid[m->jnt_bodyid[j]];
    const mjtNum* anchor = d->xanchor + 3 * j;
    const mjtNum offset[3] = {c[0] - anchor[0], c[1] - anchor[1], c[2] - anchor[2]};
    for (int k = 0; k < 3; ++k) cdof[k] = axis[k];
    cdof[3] = axis[1] * offset[2] - axis[2] * offset[1];
    cdof[4] = axis[2] * offset[0] - axis[0] * offset[2];
    cdof[5] = axis[0] * offset[1] - axis[1] * offset[0];
  }
}

// mj_comVel's cvel for hinges and slides: each body's spatial velocity
// its parent's plus cdof qdot of its dofs.
void StokesComVel(const mjModel* m, mjData* d) {
  for (int k = 0; k < 6; ++k) d->cvel[k] = 0;
  for (int i = 1; i < m->nbody; ++i) {
    mjtNum* cvel = d->cvel + 6 * i;
    const mjtNum* parent = d->cvel + 6 * m->body_parentid[i];
    for (int k = 0; k < 6; ++k) cvel[k] = parent[k];
    for (int dof = m->body_dofadr[i]; dof < m->body_dofadr[i] + m->body_dofnum[i]; ++dof) {
      for (int k = 0; k < 6; ++k) cvel[k] += d->cdof[6 * dof + k] * d->qvel[dof];
    }
  }
}

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

StokesTopology::StokesTopology(const mjModel* m) {
  RequireSupported(m);
  joint_actuators_only = JointActuatorsOnly(m);
  hinges_and_slides_only = HingesAndSlidesOnly(m);
  body_last_dof.assign(m->nbody, -1);
  for (int body = 1; body < m->nbody; ++body) {
    body_last_dof[body] = m->body_dofnum[body] > 0
                              ? m->body_dofadr[body] + m->body_dofnum[body] - 1
                              : body_last_dof[m->body_parentid[body]];
  }
}

StokesStepper::StokesStepper(const mjModel* m) : topology_(m) {
  spatial_.Resize(m->nv);
  planar_.Resize(m->nv);
  force_less_bias_.resize(m->nv);
  inverse_pivot_.resize(m->nv);
  stiffness_damping_.resize(m->nv);
  force_at_rest_.resize(m->nv);
  cdof_.resize(6 * m->nv);
  last_cdof_.resize(6 * m->nv);
  midpoint_cdof_.resize(6 * m->nv);
  last_end_qpos_.resize(m->nq);
  last_start_qpos_.resize(m->nq);
  scratch_qpos_.resize(m->nq);
}

// The fluid's resistance D = sum_s J_s^T S_s J_s enters the step here, and
// only here (a fluid whose segments do not interact: RFT): each segment's
// spatial resistance S_s (Fluid::LocalResistances, the formula the drag
// callback applies; of a planar body only its [w_z; v_x; v_y] block),
// extrapolated to the step's midpoint, 3/2 of this step's minus 1/2 of the
// last one's if the step continues the last, added to the resistance of
// its body's last dof (body_resistance), from which Solve's recursion
// carries it to the root; the fluid power reads it too. A fluid whose
// segments interact adds none (its resistance is interaction_).
template <int Dim>
void StokesStepper::AssembleResistances(const mjModel* m, const mjData* d,
                                        const Fluid* fluid, bool continues_last_step) {
  StokesBlockWorkspace<Dim>& w = Workspace<Dim>();
  w.last_segment_resistances.swap(w.segment_resistances);
  w.segment_resistances.clear();
  if (fluid) fluid->LocalResistances(m, d, &w.segment_resistances);
  const bool extrapolate = continues_last_step &&
                           w.last_segment_resistances.size() == w.segment_resistances.size();
  for (int j = 0; j < m->nv; ++j) w.body_resistance[j].setZero();
  for (size_t i = 0; i < w.segment_resistances.size(); ++i) {
    const int dof = topology_.body_last_dof[w.segment_resistances[i].body];
    if (dof < 0) continue;
    if (extrapolate) {
      w.body_resistance[dof] += 1.5 * w.segment_resistances[i].resistance -
                                0.5 * w.last_segment_resistances[i].resistance;
    } else {
      w.body_resistance[dof] += w.segment_resistances[i].resistance;
    }
  }
}

template <int Dim>
double StokesStepper::LocalFluidPower_W(const mjModel* m) {
  const StokesBlockWorkspace<Dim>& w = Workspace<Dim>();
  double power_W = 0;
  for (int j = 0; j < m->nv; ++j) {
    power_W += w.spatial_velocity[j].dot(w.body_resistance[j] * w.spatial_velocity[j]);
  }
  return power_W;
}

// Minimising 1/2 sum_b V_b^T S_b V_b + 1/2 sum_j e_j v_j^2 - f^T v over v,
// where a dof's spatial velocity is its parent dof's plus s_j v_j
// (s_j = cdof_j), dof by dof from the leaves: the subtree below dof j costs
// 1/2 V^T A_j V + p_j^T V at its velocity V, and eliminating v_j gives its
// parent A += A_j - U U^T / D_j, p += p_j + U u_j / D_j with U = A_j s_j,
// D_j = s_j.U + e_j, u_j = f_j - s_j.p_j; then, from the root,
// v_j = (u_j - U.V_parent) / D_j. With every s_j in the components
// [First, First + Dim) of the spatial vector (a planar body: [w_z; v_x;
// v_y], First = 2, Dim = 3), only that block of the A_j enters: U's, p's
// and V's other components multiply zeros of s, so the recursion runs on
// the Dim x Dim block (the same sums less terms that are exact zeros: the
// same result to round-off, at a quarter of the 6 x 6 recursion's work).
// In the code: e_j stiffness_damping, A_j articulated_resistance (from the
// body's own, body_resistance), p_j articulated_bias, U
// resistance_times_motion, u_j force_less_bias_.
template <int First, int Dim>
bool StokesStepper::SolveBlock(const mjModel* m, const double* cdof,
                               const double* stiffness_damping, const double* f, double* v) {
  using Vector = Eigen::Matrix<double, Dim, 1>;
  using Matrix = Eigen::Matrix<double, Dim, Dim>;
  StokesBlockWorkspace<Dim>& w = Workspace<Dim>();
  const int nv = m->nv;
  w.articulated_resistance = w.body_resistance;
  for (int j = 0; j < nv; ++j) w.articulated_bias[j].setZero();
  for (int j = nv - 1; j >= 0; --j) {
    const Eigen::Map<const Vector> s(cdof + 6 * j + First);
    Vector& u = w.resistance_times_motion[j];
    u.noalias() = w.articulated_resistance[j] * s;
    const double pivot = s.dot(u) + stiffness_damping[j];
    if (!(pivot > 0)) return false;
    // One division per dof (its latency is on the recursion's critical
    // path), the rest multiplications by 1 / D_j.
    inverse_pivot_[j] = 1.0 / pivot;
    force_less_bias_[j] = f[j] - s.dot(w.articulated_bias[j]);
    const int parent = m->dof_parentid[j];
    if (parent < 0) continue;
    Matrix& target = w.articulated_resistance[parent];
    target += w.articulated_resistance[j];
    target.noalias() -= u * (u.transpose() * inverse_pivot_[j]);
    w.articulated_bias[parent] +=
        w.articulated_bias[j] + u * (force_less_bias_[j] * inverse_pivot_[j]);
  }
  for (int j = 0; j < nv; ++j) {
    const Eigen::Map<const Vector> s(cdof + 6 * j + First);
    const int parent = m->dof_parentid[j];
    const Vector parent_velocity = parent < 0 ? Vector::Zero() : w.spatial_velocity[parent];
    v[j] = (force_less_bias_[j] - w.resistance_times_motion[j].dot(parent_velocity)) *
           inverse_pivot_[j];
    w.spatial_velocity[j] = parent_velocity + s * v[j];
  }
  return true;
}

bool StokesStepper::Solve(const mjModel* m, const double* cdof, const double* stiffness_damping,
                          const double* f, double* v) {
  return planar_motion_ ? SolveBlock<2, 3>(m, cdof, stiffness_damping, f, v)
                        : SolveBlock<0, 6>(m, cdof, stiffness_damping, f, v);
}

// J (6 bodies x nv) has in body b's rows the motions s_j of the dofs on
// b's chain, so J = B S with S the dofs' motions (one column each) and B
// the bodies' chains (B_bj = I if dof j moves body b), and
//   D = J^T R J = S^T (B^T R B) S,  (B^T R B)_jk = sum R_bc over b moved by
// j and c moved by k,
// summed up the tree, leaf to root, first over the rows and then over the
// columns: O(bodies x nv) blocks where J^T R J costs O(bodies^2 x nv) dense
// 6 x 6 products. Planar motions (every s in [w_z; v_x; v_y], First = 2,
// Dim = 3) read only that block of each R_bc: the others multiply exact
// zeros of s. The same sums as J^T R J in another order (StokesDenseTest:
// within 1e-12).
template <int First, int Dim>
void StokesStepper::ChainBlocks(const mjModel* m, const Fluid& fluid,
                                const Eigen::MatrixXd& resistance, Eigen::MatrixXd* blocks) {
  const int nv = m->nv;
  const std::vector<int>& bodies = fluid.InteractingBodies();
  const int count = static_cast<int>(bodies.size());
  // Rows: body_blocks_ (Dim nv x Dim bodies), block (j, c) = sum R_bc over
  // the bodies b that dof j moves.
  body_blocks_.setZero(Dim * nv, Dim * count);
  for (int b = 0; b < count; ++b) {
    const int dof = topology_.body_last_dof[bodies[b]];
    if (dof < 0) continue;
    for (int c = 0; c < count; ++c) {
      body_blocks_.block<Dim, Dim>(Dim * dof, Dim * c) +=
          resistance.block<Dim, Dim>(6 * b + First, 6 * c + First);
    }
  }
  for (int j = nv - 1; j >= 0; --j) {
    const int parent = m->dof_parentid[j];
    if (parent >= 0) body_blocks_.middleRows<Dim>(Dim * parent) += body_blocks_.middleRows<Dim>(Dim * j);
  }
  // Columns: the blocks (Dim nv x Dim nv).
  blocks->setZero(Dim * nv, Dim * nv);
  for (int c = 0; c < count; ++c) {
    const int dof = topology_.body_last_dof[bodies[c]];
    if (dof < 0) continue;
    blocks->middleCols<Dim>(Dim * dof) += body_blocks_.middleCols<Dim>(Dim * c);
  }
  for (int k = nv - 1; k >= 0; --k) {
    const int parent = m->dof_parentid[k];
    if (parent >= 0) blocks->middleCols<Dim>(Dim * parent) += blocks->middleCols<Dim>(Dim * k);
  }
}

// A fit's R_F = sum_k tau^k C_k gives blocks sum_k tau^k B(C_k), B the
// chain sums (linear): each B(C_k) once per fit, the sum at every step.
void StokesStepper::CubicBlocks(const mjModel* m, const Fluid& fluid,
                                const ResistanceCubic& cubic) {
  if (cubic.version != cubic_version_ || &fluid != cubic_fluid_of_ || dense_dim_ != cubic_dim_) {
    for (size_t k = 0; k < cubic_blocks_.size(); ++k) {
      if (dense_dim_ == 3) {
        ChainBlocks<2, 3>(m, fluid, (*cubic.coefficients)[k], &cubic_blocks_[k]);
      } else {
        ChainBlocks<0, 6>(m, fluid, (*cubic.coefficients)[k], &cubic_blocks_[k]);
      }
    }
    cubic_version_ = cubic.version;
    cubic_fluid_of_ = &fluid;
    cubic_dim_ = dense_dim_;
  }
  const double t = cubic.tau_s;
  dense_blocks_ = cubic_blocks_[0] + t * cubic_blocks_[1] + (t * t) * cubic_blocks_[2] +
                  (t * t * t) * cubic_blocks_[3];
  if (!cubic.local) return;
  if (dense_dim_ == 3) {
    AddLocalChainBlocks<2, 3>(m, fluid, *cubic.local);
  } else {
    AddLocalChainBlocks<0, 6>(m, fluid, *cubic.local);
  }
}

// The chain sums of a resistance with a block S_b on its diagonal for each
// body: block (j, k) is the sum of S_b over the bodies whose chain holds
// both dofs, the subtree sum T_j below dof j when k is j or its ancestor
// (MuJoCo numbers a dof's parent below it, so j >= k), none otherwise:
// the blocks on and below the diagonal, the ones SolveDense reads.
template <int First, int Dim>
void StokesStepper::AddLocalChainBlocks(const mjModel* m, const Fluid& fluid,
                                        const std::vector<Eigen::Matrix<double, 6, 6>>& local) {
  const int nv = m->nv;
  const std::vector<int>& bodies = fluid.InteractingBodies();
  subtree_blocks_.setZero(Dim, Dim * nv);
  for (size_t b = 0; b < bodies.size(); ++b) {
    const int dof = topology_.body_last_dof[bodies[b]];
    if (dof < 0) continue;
    subtree_blocks_.middleCols<Dim>(Dim * dof) += local[b].block<Dim, Dim>(First, First);
  }
  for (int j = nv - 1; j >= 0; --j) {
    const int parent = m->dof_parentid[j];
    if (parent < 0) continue;
    subtree_blocks_.middleCols<Dim>(Dim * parent) += subtree_blocks_.middleCols<Dim>(Dim * j);
  }
  for (int j = 0; j < nv; ++j) {
    for (int k = j; k >= 0; k = m->dof_parentid[k]) {
      dense_blocks_.block<Dim, Dim>(Dim * j, Dim * k) += subtree_blocks_.middleCols<Dim>(Dim * j);
    }
  }
}

// What R's change of frame does to the dof motions: with R = F^T R_F F
// and F = diag(G, ...) the same for every body, F commutes with B, so
// B^T R B = G^T (B^T R_F B) G block by block and D_jk = (G s_j)^T block_jk
// (G s_k): the frame changes nv motions rather than the whole R. The
// blocks are summed again only when R_F has changed (its version; a body
// swimming with a cached resistance changes only G). Planar motions stay
// planar in the frame if G keeps [w_z; v_x; v_y] apart from the rest.
bool StokesStepper::DenseBlocks(const mjModel* m, const mjData* d, const Fluid& fluid,
                                bool planar) {
  Eigen::Matrix<double, 6, 6> frame;
  long version = -1;
  ResistanceCubic cubic;
  const bool fitted = fluid.FrameResistanceCubic(m, d, &frame, &cubic);
  const Eigen::MatrixXd* frame_resistance =
      fitted ? nullptr : fluid.FrameResistance(m, d, &frame, &version);
  if (!fitted && !frame_resistance) return false;
  const bool frame_planar = planar && frame.block<2, 3>(0, 2).isZero(0.0) &&
                            frame.block<1, 3>(5, 2).isZero(0.0);
  last_dense_blocks_.swap(dense_blocks_);
  last_dense_frame_ = dense_frame_;
  last_dense_version_ = dense_version_;
  last_dense_dim_ = dense_dim_;
  dense_frame_ = frame;
  dense_dim_ = frame_planar ? 3 : 6;
  const bool same = version >= 0 && version == last_dense_version_ && &fluid == dense_fluid_of_ &&
                    dense_dim_ == last_dense_dim_;
  dense_version_ = version;
  dense_fluid_of_ = &fluid;
  if (fitted) {
    CubicBlocks(m, fluid, cubic);
  } else if (same) {
    dense_blocks_ = last_dense_blocks_;
  } else if (frame_planar) {
    ChainBlocks<2, 3>(m, fluid, *frame_resistance, &dense_blocks_);
  } else {
    ChainBlocks<0, 6>(m, fluid, *frame_resistance, &dense_blocks_);
  }
  return true;
}

// (D + diag(stiffness_damping)) v = f with D at the step's midpoint,
// 3/2 of this step's B^T R B and -1/2 of the last one's, both on the
// midpoint's s: D_jk = 3/2 u_j^T block_jk u_k - 1/2 w_j^T last block_jk
// w_k, u = G s and w = G_last s (DenseBlocks). Symmetric positive definite
// when solvable: Cholesky.
template <int First, int Dim>
bool StokesStepper::SolveDense(const mjModel* m, const double* stiffness_damping,
                               const double* f, double* v) {
  using Vector = Eigen::Matrix<double, Dim, 1>;
  const int nv = m->nv;
  const Eigen::Map<const Eigen::Matrix<double, 6, Eigen::Dynamic>> motion(midpoint_cdof_.data(), 6,
                                                                           nv);
  frame_motion_.noalias() = dense_frame_ * motion;
  if (extrapolate_dense_) last_frame_motion_.noalias() = last_dense_frame_ * motion;
  dense_system_.resize(nv, nv);
  for (int k = 0; k < nv; ++k) {
    const Vector u_k = frame_motion_.col(k).template segment<Dim>(First);
    for (int j = k; j < nv; ++j) {
      const Vector u_j = frame_motion_.col(j).template segment<Dim>(First);
      const double now = u_j.dot(dense_blocks_.block<Dim, Dim>(Dim * j, Dim * k) * u_k);
      if (!extrapolate_dense_) {
        dense_system_(j, k) = now;
        continue;
      }
      const Vector w_k = last_frame_motion_.col(k).template segment<Dim>(First);
      const Vector w_j = last_frame_motion_.col(j).template segment<Dim>(First);
      dense_system_(j, k) =
          1.5 * now - 0.5 * w_j.dot(last_dense_blocks_.block<Dim, Dim>(Dim * j, Dim * k) * w_k);
    }
  }
  Eigen::Map<Eigen::VectorXd> velocity(v, nv);
  const Eigen::Map<const Eigen::VectorXd> force(f, nv);
  Eigen::MatrixXd system = dense_system_;
  for (int j = 0; j < nv; ++j) system(j, j) += stiffness_damping[j];
  const Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> llt(system);
  if (llt.info() != Eigen::Success) return false;
  velocity = llt.solve(force);
  // v^T J^T R J v: the power the step gives the fluid.
  fluid_power_W_ = velocity.dot(dense_system_.selfadjointView<Eigen::Lower>() * velocity);
  return true;
}

bool StokesStepper::Step(const mjModel* m, mjData* d, const Fluid* fluid) {
  const double h = m->opt.timestep;
  const bool sensors = !(m->opt.disableflags & mjDSBL_SENSOR);
  // Position stage without the mass matrix (mj_fwdPosition less mj_crb,
  // mj_factorM and the constraints).
  mju_copy(last_start_qpos_.data(), d->qpos, m->nq);
  mj_kinematics(m, d);
  ComPos(m, d);
  mj_camlight(m, d);
  mj_tendon(m, d);
  Transmission(m, d);
  if (sensors) mj_sensorPos(m, d);
  ExtrapolateToMidpoint(m, d, fluid);
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
    force_at_rest_[j] = d->qfrc_passive[j] + d->qfrc_actuator[j] + d->qfrc_applied[j];
  }
  StiffnessAndDamping(m, d, h, stiffness_damping_.data());
  const bool solved =
      dense_fluid_
          ? (dense_dim_ == 3
                 ? SolveDense<2, 3>(m, stiffness_damping_.data(), force_at_rest_.data(), d->qvel)
                 : SolveDense<0, 6>(m, stiffness_damping_.data(), force_at_rest_.data(), d->qvel))
          : Solve(m, midpoint_cdof_.data(), stiffness_damping_.data(), force_at_rest_.data(),
                  d->qvel);
  if (!solved) return false;
  if (!fluid) {
    fluid_power_W_ = 0;
  } else if (!dense_fluid_) {  // SolveDense sets a dense resistance's
    fluid_power_W_ = planar_motion_ ? LocalFluidPower_W<3>(m) : LocalFluidPower_W<6>(m);
  }
  mju_zero(d->qacc, m->nv);
  ComVel(m, d);
  if (sensors) mj_sensorVel(m, d);
  mj_integratePos(m, d->qpos, d->qvel, h);
  d->time += h;
  mju_copy(last_end_qpos_.data(), d->qpos, m->nq);
  last_end_time_ = d->time;
  return true;
}

void StokesStepper::StoreHistory(const mjModel* m, const mjData* d, int offset) const {
  // d->userdata is the program's buffer, not part of const mjData.
  double* block = d->userdata + offset;
  block[0] = has_last_step_ ? 1.0 : 0.0;
  block[1] = last_end_time_;
  mju_copy(block + 2, last_start_qpos_.data(), m->nq);
  mju_copy(block + 2 + m->nq, last_end_qpos_.data(), m->nq);
}

void StokesStepper::LoadHistory(const mjModel* m, mjData* d, const Fluid* fluid, int offset) {
  const double* block = d->userdata + offset;
  has_last_step_ = false;
  if (block[0] == 0.0) return;
  // The last step's position stage and resistances, as it computed them.
  mju_copy(scratch_qpos_.data(), d->qpos, m->nq);
  mju_copy(d->qpos, block + 2, m->nq);
  mj_kinematics(m, d);
  ComPos(m, d);
  ExtrapolateToMidpoint(m, d, fluid);
  mju_copy(d->qpos, scratch_qpos_.data(), m->nq);
  mju_copy(last_start_qpos_.data(), block + 2, m->nq);
  mju_copy(last_end_qpos_.data(), block + 2 + m->nq, m->nq);
  last_end_time_ = block[1];
}

void StokesStepper::ComPos(const mjModel* m, mjData* d) {
  if (topology_.hinges_and_slides_only) {
    StokesComPos(m, d);
  } else {
    mj_comPos(m, d);
  }
}

void StokesStepper::ComVel(const mjModel* m, mjData* d) {
  if (topology_.hinges_and_slides_only) {
    StokesComVel(m, d);
  } else {
    mj_comVel(m, d);
  }
}

void StokesStepper::Transmission(const mjModel* m, mjData* d) {
  if (!topology_.joint_actuators_only || !moments_set_) {
    mj_transmission(m, d);
    moments_set_ = true;
    return;
  }
  JointTransmission(m, d);
}

void StokesStepper::Actuation(const mjModel* m, mjData* d) {
  if (topology_.joint_actuators_only) {
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
                                          const Fluid* fluid) {
  last_cdof_.swap(cdof_);
  mju_copy(cdof_.data(), d->cdof, 6 * m->nv);
  const bool planar = PlanarMotions(cdof_.data(), m->nv);
  // A step that changes between planar and spatial motions starts afresh
  // (the two keep different blocks of S).
  const bool continues_last_step =
      has_last_step_ && d->time == last_end_time_ &&
      std::equal(last_end_qpos_.begin(), last_end_qpos_.end(), d->qpos) &&
      planar == planar_motion_;
  planar_motion_ = planar;
  has_last_step_ = true;
  // The midpoint's B^T R B from this step's and the last one's: the same
  // 3/2 and -1/2 of R's, as B is constant.
  dense_fluid_ = fluid && DenseBlocks(m, d, *fluid, planar);
  extrapolate_dense_ = dense_fluid_ && continues_last_step && last_dense_dim_ == dense_dim_;
  if (planar) {
    AssembleResistances<3>(m, d, fluid, continues_last_step);
  } else {
    AssembleResistances<6>(m, d, fluid, continues_last_step);
  }
  if (!continues_last_step) {
    midpoint_cdof_ = cdof_;
    return;
  }
  for (size_t i = 0; i < cdof_.size(); ++i) midpoint_cdof_[i] = 1.5 * cdof_[i] - 0.5 * last_cdof_[i];
}

}  // namespace ipmc
