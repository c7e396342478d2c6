#include "plugin/fluid/near_wall_rft.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "sim/base/numbers.h"

namespace ipmc {

DragCoefficients NearWallCoefficients(double viscosity_Pa_s, double radius_m,
                                      double wall_distance_m) {
  const double log_term = std::log(2.0 * wall_distance_m / radius_m);
  return {4.0 * kPi * viscosity_Pa_s / log_term, 2.0 * kPi * viscosity_Pa_s / log_term};
}

void ValidateNearWallDistance(double wall_distance_m, double radius_m) {
  if (!(wall_distance_m > radius_m) || !std::isfinite(wall_distance_m)) {
    std::ostringstream msg;
    msg << "rft drag: coefficients = near_wall needs " << kAttrWallDistance << " > "
        << kAttrEquivalentRadius << " = " << radius_m << " m (got " << wall_distance_m << ")";
    throw std::invalid_argument(msg.str());
  }
}

}  // namespace ipmc
