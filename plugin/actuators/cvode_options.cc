#include "plugin/actuators/cvode_options.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace ipmc {

void CvodeOptions::Validate() const {
  if (linear_solver != CvodeLinearSolver::kBlockSchur &&
      linear_solver != CvodeLinearSolver::kDense && linear_solver != CvodeLinearSolver::kBand) {
    throw std::invalid_argument(
        "ipmc actuator: linear_solver must be kBlockSchur, kDense or kBand");
  }
  if (!(rel_tol >= 1e-14 && rel_tol <= 1e-2)) {
    std::ostringstream out;
    out << "ipmc actuator: rel_tol must be in [1e-14, 1e-2] (got " << rel_tol << ")";
    throw std::invalid_argument(out.str());
  }
  if (!std::isfinite(abs_tol_mm) || abs_tol_mm <= 0) {
    std::ostringstream out;
    out << "ipmc actuator: abs_tol_mm must be finite and > 0 (got " << abs_tol_mm << ")";
    throw std::invalid_argument(out.str());
  }
  if (max_steps < 1) {
    std::ostringstream out;
    out << "ipmc actuator: max_steps must be >= 1 (got " << max_steps << ")";
    throw std::invalid_argument(out.str());
  }
}

}  // namespace ipmc
