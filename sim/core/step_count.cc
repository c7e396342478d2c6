#include "sim/core/step_count.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace ipmc {

long CheckedStepCount(double interval_s, double timestep_s, long min_steps, const std::string& what) {
  std::ostringstream msg;
  msg.precision(6);
  if (!std::isfinite(timestep_s) || timestep_s <= 0.0) {
    msg << what << ": the model's time step must be finite and > 0 s (got " << timestep_s << ")";
    throw std::invalid_argument(msg.str());
  }
  if (!std::isfinite(interval_s) || interval_s <= 0.0) {
    msg << what << ": must last a finite time > 0 s (got " << interval_s << " s)";
    throw std::invalid_argument(msg.str());
  }
  const double steps = std::round(interval_s / timestep_s);
  if (steps < static_cast<double>(min_steps) || steps > kMaxStepsPerInterval) {
    msg << what << " of " << interval_s << " s takes " << steps << " steps of " << timestep_s
        << " s; allowed [" << min_steps << ", " << kMaxStepsPerInterval << "]";
    throw std::invalid_argument(msg.str());
  }
  return static_cast<long>(steps);
}

}  // namespace ipmc
