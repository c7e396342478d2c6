// What a caller chooses of the CVODE integrator
// (plugin/actuators/cvode_integrator.h): its linear solver, tolerances and
// step cap, apart from the integrator so that SUNDIALS's headers stay in
// the files that call SUNDIALS.
#pragma once

namespace ipmc {

// Default CVODE tolerances: relative, and absolute per state (mm or V).
constexpr double kRelTol = 1e-8;
constexpr double kAbsTol = 1e-10;
// Default cap on internal steps per Advance call.
constexpr int kMaxStepsPerAdvance = 100000;

enum class CvodeLinearSolver { kBlockSchur, kDense, kBand };

struct CvodeOptions {
  CvodeLinearSolver linear_solver = CvodeLinearSolver::kBlockSchur;
  double rel_tol = kRelTol;      // in [1e-14, 1e-2]
  double abs_tol_mm = kAbsTol;   // > 0, finite; applied to every state
  int max_steps = kMaxStepsPerAdvance;  // >= 1, per Advance call

  // Throws std::invalid_argument naming the field and its allowed range.
  void Validate() const;
};

}  // namespace ipmc
