// Time stepping of a body in Stokes flow (Reynolds number << 1): no
// inertia, the generalised velocity follows from the balance of forces.
//
// With the RFT drag linear in the velocity, -D(q) qdot with
// D = sum over segments J_s^T S_s J_s (S_s the segment's spatial
// resistance, plugin/fluid/rft_drag.h, J_s its body's Jacobian), the
// joints' damping C and stiffness K (diagonal) and every other force f
// (the active moments in qfrc_actuator, qfrc_applied, other passive
// forces), the balance is
//   D(q) qdot + C qdot = f(q, t) - K (q - q_spring).
// One step of h is backward Euler in the stiffness, with the resistance at
// the step's midpoint, extrapolated from this step's and the last one's:
//   (D_(n+1/2) + C + h K) v = f(q_n, t_n + h) - K (q_n - q_spring),
//   q_(n+1) = q_n + h v,  D_(n+1/2) = 3/2 D(q_n) - 1/2 D(q_(n-1)),
// which is stable at any h for K, C >= 0 (the position enters D only, not
// the stiff terms), and makes the body's swim per cycle second order in h
// where D(q_n) alone gives first order (docs/DYNAMICS.md). The step is set by what drives
// the body (the controller's sample, the wave), not by the hinges' stiff
// relaxation (D/K ~ microseconds for a sub-segment of the IPMC strip). An
// affine actuator bias (a servo's -kp q - kv qdot on a joint) enters the
// same way, as stiffness and damping. The matrix is never formed: the
// solve is the articulated-body recursion (Featherstone, "Rigid Body
// Dynamics Algorithms", 2008, ch. 7) with the spatial resistances in place
// of the spatial inertias, one pass leaf to root and one back over the
// dofs of MuJoCo's tree, so a step costs O(number of dofs).
//
// MuJoCo computes everything else: kinematics, the passive and actuator
// forces (mjcb_passive, mjcb_control run as in mj_forward, but
// mjcb_control with d->time set to the step's end, so that the IPMC
// actuators' active moments are those of t_n + h and the shape at t_n + h
// balances them; after a step the actuators' state is at the new d->time),
// sensors. After
// a step qvel holds v (the velocity over the step), qacc is zero,
// qfrc_passive holds the passive forces at zero velocity (so without the
// drag), sensordata is computed from q_n and v, and time has advanced by h;
// what only inertia needs (the mass matrix qM, cinert, cdof_dot) is not
// computed on models of hinges and slides.
// Not supported (the constructor refuses them): contacts, joint or tendon
// limits, equality constraints, and actuators with activation dynamics.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <Eigen/StdVector>
#include <array>
#include <string>
#include <vector>

#include "plugin/fluid/fluid_model.h"
#include "ipmc_swim/fields.h"

namespace ipmc {

// True if every actuator drives a hinge or slide joint directly with a
// fixed or affine gain, no or an affine bias and no activation (the IPMC
// motors, the gaits' servos): their moments are the constant gears, so the
// two functions below can replace MuJoCo's, whose dense nu x nv moment
// matrix makes a step's cost quadratic in the number of hinges.
bool JointActuatorsOnly(const mjModel* m);
// mj_transmission for such a model in O(nu): the lengths gear q and each
// moment row's gear at its joint's dof; the rest of each row must be zero,
// as mj_transmission leaves it.
void JointTransmission(const mjModel* m, mjData* d);
// mj_fwdActuation for such a model in O(nu), the same numbers; bad
// controls (which MuJoCo warns of and zeroes) and disabled actuation go
// to mj_fwdActuation itself.
void JointActuation(const mjModel* m, mjData* d);

// True if every joint is a hinge or a slide (no free or ball joints).
bool HingesAndSlidesOnly(const mjModel* m);
// For such a model, what the Stokes step needs of mj_comPos and
// mj_comVel, the same numbers bit for bit (StokesKinematicsTest):
// subtree_com and cdof, without the inertias in the centre-of-mass frames
// (cinert); cvel, without cdof_dot. A step without inertia reads neither,
// nor the mass matrix (qM), which it does not compute either.
void StokesComPos(const mjModel* m, mjData* d);
void StokesComVel(const mjModel* m, mjData* d);

// What a model fixes for every step of the Stokes stepper: its tree of
// dofs and which of MuJoCo's stages have the O(nv) replacements above.
struct StokesTopology {
  // Throws std::invalid_argument naming what the model has that the
  // stepper does not support.
  explicit StokesTopology(const mjModel* m);

  // The last dof of each body's chain of dofs (its own last dof or its
  // nearest moving ancestor's), -1 for a body fixed to the world.
  std::vector<int> body_last_dof;
  bool hinges_and_slides_only = false;  // HingesAndSlidesOnly
  bool joint_actuators_only = false;    // JointActuatorsOnly
};

// The recursion's workspace in Dim components of the spatial vectors (6:
// all of [w; v], 3: [w_z; v_x; v_y] of a planar motion), per dof, and per
// segment its resistance's block this step and the last.
template <int Dim>
struct StokesBlockWorkspace {
  using Vector = Eigen::Matrix<double, Dim, 1>;
  using Matrix = Eigen::Matrix<double, Dim, Dim>;
  std::vector<Matrix, Eigen::aligned_allocator<Matrix>> articulated_resistance;
  // The resistance of the segments on the dof's body: its share of D.
  std::vector<Matrix, Eigen::aligned_allocator<Matrix>> body_resistance;
  // The subtree's bias p, U = A s (articulated resistance times the dof's
  // motion) and the spatial velocity the solve gives.
  std::vector<Vector, Eigen::aligned_allocator<Vector>> articulated_bias, resistance_times_motion,
      spatial_velocity;
  BodyResistanceBlocks<Dim> segment_resistances, last_segment_resistances;
  void Resize(int nv) {
    articulated_resistance.resize(nv);
    body_resistance.resize(nv);
    articulated_bias.resize(nv);
    resistance_times_motion.resize(nv);
    spatial_velocity.resize(nv);
  }
};

class StokesStepper {
 public:
  // Throws std::invalid_argument naming what the model has that the
  // stepper does not support.
  explicit StokesStepper(const mjModel* m);

  // One step of m->opt.timestep. `fluid` may be null (no drag: the
  // joints' damping alone must then resist every dof). Returns false and
  // leaves d's position and time unchanged if a dof has no resistance at
  // all (the force balance is singular); the caller reports that. A
  // fluid whose segments interact (Fluid::InteractionResistance, the
  // Stokeslets) gives a dense resistance R over its bodies: D = J^T R J is
  // formed (nv x nv) and factored (Cholesky) in place of the recursion,
  // O(nv^3), with R extrapolated to the step's midpoint as the local S are
  // (ChainBlocks has how J's chains enter).
  bool Step(const mjModel* m, mjData* d, const Fluid* fluid);
  // The history's home in mjData (ipmc_swim.h, "State"): HistorySize(m)
  // values of d->userdata: whether a step was made, its end time, and its
  // start and end positions.
  static int HistorySize(const mjModel* m) { return 2 + 2 * m->nq; }
  // Writes the history to d->userdata from `offset`.
  void StoreHistory(const mjModel* m, const mjData* d, int offset) const;
  // Takes the history StoreHistory wrote there, for d or for another
  // mjData of the same model copied into d: the last step's motions and
  // resistances are computed again at its start position (on d, whose
  // position stage the next Step computes afresh), so that the next Step
  // is the one the writer would have made, bit for bit, with a fluid
  // whose resistance depends on the position alone (a dense fluid's
  // cache, kept within its shape tolerance, is this stepper's own).
  void LoadHistory(const mjModel* m, mjData* d, const Fluid* fluid, int offset);
  // Forgets the last step: the next starts afresh.
  void ForgetHistory() { has_last_step_ = false; }

  // The power [W] the last step gave the fluid: v^T D v with the step's
  // velocity v and the resistance D at its midpoint that it solved with,
  // so that over a step the generalised forces' work f . v h is this, the
  // joints' damping and the springs' energy to round-off
  // (docs/ENERGY.md); 0 without a fluid.
  double fluid_power_W() const { return fluid_power_W_; }

 private:
  // Each dof's body_resistance: the segments' resistances at the step's
  // midpoint, on their bodies' last dofs (the [w_z; v_x; v_y] block if
  // planar_motion_, all of S otherwise); the recursion starts from them.
  template <int Dim>
  void AssembleResistances(const mjModel* m, const mjData* d, const Fluid* fluid,
                           bool continues_last_step);
  // Sum over the dofs of V^T body_resistance V, V their spatial velocities
  // in the recursion's last solve.
  template <int Dim>
  double LocalFluidPower_W(const mjModel* m);
  // Solves (D + diag(stiffness_damping)) v = f for v, D from the dofs'
  // motions cdof and the assembled resistances. Returns false if the
  // system is singular. Planar motions (planar_motion_) take the 3 x 3
  // recursion, others the 6 x 6 one.
  bool Solve(const mjModel* m, const double* cdof, const double* stiffness_damping,
             const double* f, double* v);
  template <int First, int Dim>
  bool SolveBlock(const mjModel* m, const double* cdof, const double* stiffness_damping,
                  const double* f, double* v);
  // The dense solve with a fluid whose segments interact (Step), from
  // this step's and the last one's dense_blocks_ and frames.
  template <int First, int Dim>
  bool SolveDense(const mjModel* m, const double* stiffness_damping, const double* f, double* v);
  // The chain sums `blocks` (dense_blocks_'s form) of the resistance R_F
  // over the fluid's InteractingBodies() (ExtrapolateToMidpoint).
  template <int First, int Dim>
  void ChainBlocks(const mjModel* m, const Fluid& fluid, const Eigen::MatrixXd& resistance,
                   Eigen::MatrixXd* blocks);
  // dense_blocks_ of a fluid's fitted R_F (Fluid::FrameResistanceCubic), in
  // dense_dim_: the sums of the cubic's coefficients, made once per fit.
  void CubicBlocks(const mjModel* m, const Fluid& fluid, const ResistanceCubic& cubic);
  // dense_blocks_ += the chain sums of a cubic's local part (one 6 x 6 per
  // interacting body, on R_F's diagonal), on and below the diagonal.
  template <int First, int Dim>
  void AddLocalChainBlocks(const mjModel* m, const Fluid& fluid,
                           const std::vector<Eigen::Matrix<double, 6, 6>>& local);
  // This step's dense_blocks_ and frame from the fluid's FrameResistance,
  // the last step's kept (ExtrapolateToMidpoint); false if the fluid has
  // no dense resistance.
  bool DenseBlocks(const mjModel* m, const mjData* d, const Fluid& fluid, bool planar);
  // Extrapolates S and cdof to the step's midpoint and assembles the
  // local resistances (Step).
  void ExtrapolateToMidpoint(const mjModel* m, const mjData* d, const Fluid* fluid);
  // mj_transmission and mj_fwdActuation: JointTransmission and
  // JointActuation if joint_actuators_only (after one mj_transmission,
  // which sets the moments' zeros), MuJoCo's own otherwise.
  void Transmission(const mjModel* m, mjData* d);
  void Actuation(const mjModel* m, mjData* d);
  // mj_comPos and mj_comVel: StokesComPos and StokesComVel if
  // hinges_and_slides_only, MuJoCo's own otherwise.
  void ComPos(const mjModel* m, mjData* d);
  void ComVel(const mjModel* m, mjData* d);
  template <int Dim>
  StokesBlockWorkspace<Dim>& Workspace() {
    if constexpr (Dim == 6) {
      return spatial_;
    } else {
      return planar_;
    }
  }

  const StokesTopology topology_;

  // The per-step workspace.
  StokesBlockWorkspace<6> spatial_;
  StokesBlockWorkspace<3> planar_;
  // Per dof: f_j - s_j . p_j, 1 / D_j, h K + C, and the forces at zero
  // velocity.
  std::vector<double> force_less_bias_, inverse_pivot_, stiffness_damping_, force_at_rest_;
  // The dense resistance of a fluid whose segments interact, in its frame
  // (Fluid::FrameResistance: R = F^T R_F F), summed over the dofs' chains
  // (ChainBlocks): block (j, k), Dim x Dim (the planar motion's or all of
  // [w; v]), is sum R_F,bc over the bodies b moved by dof j and c moved by
  // dof k, so that D_jk = (G s_j)^T block (G s_k). This step's and the
  // last step's, with their frames G, R_F's versions and dense_dim_ (3:
  // planar, 6); body_blocks_ is scratch.
  Eigen::MatrixXd dense_blocks_, last_dense_blocks_, body_blocks_;
  Eigen::Matrix<double, 6, 6> dense_frame_, last_dense_frame_;
  long dense_version_ = -1, last_dense_version_ = -1;
  int dense_dim_ = 0, last_dense_dim_ = 0;
  const Fluid* dense_fluid_of_ = nullptr;  // whose version dense_version_ is
  bool extrapolate_dense_ = false;  // the step continues the last with the same form
  // The chain sums of a fitted R_F's four coefficients (CubicBlocks), of
  // which fluid's cubic of which version, in which dense_dim_.
  std::array<Eigen::MatrixXd, 4> cubic_blocks_;
  Eigen::MatrixXd subtree_blocks_;  // AddLocalChainBlocks' T_j, scratch
  long cubic_version_ = -1;
  const Fluid* cubic_fluid_of_ = nullptr;
  int cubic_dim_ = 0;
  // The midpoint's dof motions in this step's frame and the last one's,
  // and D = J^T R J; scratch.
  Eigen::Matrix<double, 6, Eigen::Dynamic> frame_motion_, last_frame_motion_;
  Eigen::MatrixXd dense_system_;

  // What carries from step to step: this step's, the last step's and the
  // midpoint's cdof, where the last step ended (a step that starts
  // elsewhere does not extrapolate), and the step's form.
  std::vector<double> cdof_, last_cdof_, midpoint_cdof_, last_start_qpos_, last_end_qpos_;
  std::vector<double> scratch_qpos_;  // d's position while LoadHistory computes
  double last_end_time_ = 0;
  bool has_last_step_ = false;
  // Every dof moves in the x-y plane (no w_x, w_y, v_z) at the step's
  // start and so at its midpoint: the segments' resistances and the
  // recursion take 3 x 3 blocks.
  bool planar_motion_ = false;
  bool dense_fluid_ = false;  // the fluid gave a dense resistance
  bool moments_set_ = false;  // the first mj_transmission has run
  double fluid_power_W_ = 0;
};

}  // namespace ipmc
