// The Stokes resistance of a whole sphere or ellipsoid (a swimmer's head),
// exact for the body alone in unbounded fluid, and its spatial resistance
// about any point: what RFT (plugin/fluid/rft_drag.h) adds for the geoms
// that are not slender.
//
// An ellipsoid of semi-axes c_1, c_2, c_3 in a fluid of viscosity mu
// (Oberbeck 1876 for translation; Edwardes 1892 and Jeffery 1922 for
// rotation; Kim & Karrila, Microhydrodynamics, 1991, sec. 3.3), with
//   chi = int_0^inf dl / D = 2 R_F(c_1^2, c_2^2, c_3^2),
//   alpha_i = int_0^inf dl / ((c_i^2 + l) D) = 2/3 R_D(c_j^2, c_k^2, c_i^2),
//   D = sqrt(prod_k (c_k^2 + l)), R_F and R_D Carlson's elliptic integrals:
//   translation along axis i   F_i = -16 pi mu U / (chi + c_i^2 alpha_i)
//   rotation about axis i      T_i = -16 pi mu (c_j^2 + c_k^2) Omega /
//                                     (3 (c_j^2 alpha_j + c_k^2 alpha_k)),
// the drag along (about) a principal axis, uncoupled. A sphere of radius a:
// 6 pi mu a and 8 pi mu a^3 (Stokes 1851).
#pragma once

#include <Eigen/Core>

#include "plugin/mjcf/spatial_algebra.h"

namespace ipmc {

// The drag per velocity along each principal axis [N s/m] and per angular
// velocity about it [N m s].
struct PrincipalResistance {
  Eigen::Vector3d translation_N_s_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d rotation_N_m_s = Eigen::Vector3d::Zero();
};

PrincipalResistance EllipsoidResistance(const Eigen::Vector3d& semi_axes_m,
                                        double viscosity_Pa_s);

// The spatial resistance S about the point c_W of a body centred at
// center_W whose principal axes are the columns of axes_W: the drag wrench
// [torque about c; force] is -S [w; v_c]. With K_t = Q diag(translation)
// Q^T, K_r = Q diag(rotation) Q^T and r = center - c,
//   S = [ K_r - [r x] K_t [r x]   [r x] K_t ]
//       [ -K_t [r x]              K_t       ].
Matrix6 PrincipalResistanceAbout(const PrincipalResistance& principal,
                                 const Eigen::Vector3d& center_W, const Eigen::Matrix3d& axes_W,
                                 const Eigen::Vector3d& c_W);

}  // namespace ipmc
