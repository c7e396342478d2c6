// RFT near a no-slip plane wall: the drag coefficients of a slender body
// parallel to the wall (Katz, Blake & Paveri-Fontana, J. Fluid Mech. 72,
// 529-540, 1975), for resistive-force theory (rft_drag.h,
// `ipmc_rft_coefficients = near_wall`).
//
// For a slender body of radius a whose centreline is parallel to the wall a
// distance h from it, a << h << lambda, moving parallel to the wall:
//   xi_n = 4 pi mu / ln(2 h / a),   xi_t = 2 pi mu / ln(2 h / a)   [N s/m^2]
// (normal to the wall xi_n would be 4 pi mu / (ln(2 h / a) - 1)). The wall
// screens the far field, so 2 h takes the place of the wavelength of the
// free-space coefficients and the ratio xi_n / xi_t is exactly 2. The
// swimmer beats in a plane parallel to the wall (docs/FLUIDS.md), so the
// parallel pair is the one that acts; it is used for every direction.
#pragma once

#include "plugin/fluid/rft_drag.h"

namespace ipmc {

DragCoefficients NearWallCoefficients(double viscosity_Pa_s, double radius_m,
                                      double wall_distance_m);

// Throws std::invalid_argument naming the fields unless h > a (which keeps
// ln(2 h / a) > ln 2 > 0; the formula itself wants h >> a).
void ValidateNearWallDistance(double wall_distance_m, double radius_m);

}  // namespace ipmc
