// The resistance of a body held rigid in the library's fluid: the 6 x 6
// matrix of the force [N] and torque [N m] the fluid exerts on the whole
// body, about the world origin and along the world axes, per unit of its
// rigid velocity [m/s] and angular velocity [rad/s]:
//   [F; T] = R [v; w],  rows Fx Fy Fz Tx Ty Tz, columns vx vy vz wx wy wz,
// under any of the fluid models (docs/FLUIDS.md), from the same ipmc_rft_*
// and ipmc_fluid_* fields Attach reads (docs/LIBRARY.md). In Stokes flow R
// is symmetric (the reciprocal theorem) and negative definite (the fluid
// takes power from every motion); a body whose parts interact through the
// fluid (the dense models) has them interact here too.
//
// Purcell's propulsion matrix for an axis e (Purcell, PNAS 94, 11307,
// 1997): the force and torque along e that an outside agent exerts on the
// body moving with speed U and rotation rate Omega along e,
//   F = A U + B Omega,  N = B U + D Omega,
// A = -e.R_Fv.e, B = -e.R_Fw.e, D = -e.R_Tw.e. A rotating helix's thrust
// is |B| Omega, its torque D Omega, its drag when towed A U.
#pragma once

#include <mujoco/mujoco.h>

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace ipmc {

// What the program imposes over the model's fields (empty: the model's).
struct ResistanceSettings {
  std::string fluid_model;   // ipmc_fluid_model's values: rft, stokeslets, ribbon, plates
  std::string coefficients;  // ipmc_rft_coefficients' values: gray_hancock, lighthill, ...
  // Fluid models' parameters by their <custom> field, in the field's SI
  // unit ("ipmc_fluid_stokeslet_points_per_m", 4000).
  std::vector<std::pair<std::string, double>> fluid_parameters;
};

// R (row-major, 36 values) of the model at the positions d->qpos holds
// (the rest of d is not read; d is not changed). Throws
// std::invalid_argument with a one-line message naming the field for a
// model without ipmc_rft_viscosity_Pa_s, a malformed field or setting, or
// a geom the chosen model cannot represent.
std::array<double, 36> RigidBodyResistance(const mjModel* m, const mjData* d,
                                           const ResistanceSettings& settings = {});

struct PropulsionMatrix {
  double a_N_s_m = 0.0;   // A: force per speed along the axis
  double b_N_s = 0.0;     // B: force per rotation rate (and torque per speed)
  double d_N_m_s = 0.0;   // D: torque per rotation rate
};
// Purcell's A, B, D of R for the world axis `axis` (0, 1 or 2).
PropulsionMatrix Propulsion(const std::array<double, 36>& resistance, int axis);

}  // namespace ipmc
