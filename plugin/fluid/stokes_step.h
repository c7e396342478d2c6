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
// drag), sensordata is computed from q_n and v, and time has advanced by h.
// Not supported (the constructor refuses them): contacts, joint or tendon
// limits, equality constraints, and actuators with activation dynamics.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <Eigen/StdVector>
#include <string>
#include <vector>

#include "plugin/fluid/fluid_model.h"
#include "plugin/fluid/rft_drag.h"
#include "plugin/mjcf/dynamics.h"

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

class StokesStepper {
 public:
  // Throws std::invalid_argument naming what the model has that the
  // stepper does not support.
  explicit StokesStepper(const mjModel* m);

  // One step of m->opt.timestep. `fluid` may be null (no drag: the
  // joints' damping alone must then resist every dof). Returns false and
  // leaves d's position and time unchanged if a dof has no resistance at
  // all (the force balance is singular); the caller reports that. A
  // nonlocal fluid (Stokeslets, whose segments interact) gives a dense
  // resistance over the bodies: D = J^T R J is formed (nv x nv) and
  // factored (LDL^T) in place of the recursion, O(nv^3), with R
  // extrapolated to the step's midpoint as the local S are.
  bool Step(const mjModel* m, mjData* d, const FluidModel* fluid);

 private:
  // articulated_ = each dof's own share of D: the segments' resistances at
  // the step's midpoint (midpoint_resistances_), on their bodies' last dofs.
  void AssembleResistances(const mjModel* m);
  // Solves (D + diag(extra)) v = f for v, D from the dofs' motions cdof
  // and the assembled articulated_. Returns false if the system is
  // singular.
  bool Solve(const mjModel* m, const double* cdof, const double* extra, const double* f,
             double* v);

  using Vector6 = Eigen::Matrix<double, 6, 1>;
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  // The last dof of each body's chain of dofs (its own last dof or its
  // nearest moving ancestor's), -1 for a body fixed to the world.
  std::vector<int> body_node_;
  // Per dof: articulated resistance, bias, U = A s, u, and s.A.s + extra.
  std::vector<Matrix6, Eigen::aligned_allocator<Matrix6>> articulated_;
  std::vector<Vector6, Eigen::aligned_allocator<Vector6>> bias_, u_vector_, velocity_;
  // mj_transmission and mj_fwdActuation: JointTransmission and
  // JointActuation if JointActuatorsOnly (after one mj_transmission, which
  // sets the moments' zeros), MuJoCo's own otherwise.
  void Transmission(const mjModel* m, mjData* d);
  void Actuation(const mjModel* m, mjData* d);
  bool joint_actuators_only_ = false, moments_set_ = false;
  // Extrapolates S and cdof to the step's midpoint (Step).
  void ExtrapolateToMidpoint(const mjModel* m, const mjData* d, const FluidModel* fluid);
  // The dense solve with a nonlocal fluid (Step).
  bool SolveDense(const mjModel* m, const FluidModel& fluid, const double* extra,
                  const double* f, double* v);
  Eigen::MatrixXd dense_, last_dense_, midpoint_dense_;

  std::vector<double> u_, pivot_, diagonal_, force_;
  // This step's, the last step's and the midpoint's cdof and S, and where
  // the last step ended (a step that starts elsewhere does not extrapolate).
  std::vector<double> cdof_, last_cdof_, midpoint_cdof_, end_qpos_;
  RftDrag::BodyResistances resistances_, last_resistances_, midpoint_resistances_;
  double end_time_ = 0;
  bool have_last_ = false;
};

}  // namespace ipmc
