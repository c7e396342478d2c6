#include "sim/core/step_resolution.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <memory>
#include <sstream>

#include "ipmc_swim/ipmc_swim.h"

namespace ipmc {
namespace {

constexpr double kTwoPi = 6.283185307179586;

struct DataDelete {
  void operator()(mjData* d) const { mj_deleteData(d); }
};

// The largest eigenvalue of M^-1 A (A symmetric, M positive definite).
double LargestRate(const Eigen::MatrixXd& a, const Eigen::MatrixXd& mass) {
  const Eigen::MatrixXd symmetric = 0.5 * (a + a.transpose());
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(symmetric, mass,
                                                                        Eigen::EigenvaluesOnly);
  if (solver.info() != Eigen::Success) return 0.0;
  return std::max(0.0, solver.eigenvalues().maxCoeff());
}

std::string Milliseconds(double t_s) {
  std::ostringstream text;
  text << std::setprecision(3) << t_s * 1e3 << " ms";
  return text.str();
}

}  // namespace

bool StepResolution::Resolved() const {
  return !explicit_drag || (swim_error <= kMaxSwimStepError &&
                            timestep_s <= kMaxStepPerDragRelaxation * drag_relaxation_s);
}

StepResolution MeasureStepResolution(const mjModel* m, const mjData* d, double frequency_Hz) {
  StepResolution step;
  step.timestep_s = step.resolving_timestep_s = m->opt.timestep;
  if (!IsAttached(d) || StokesDynamics(d) || !FluidOf(d).drag || !(frequency_Hz > 0.0)) {
    return step;
  }
  step.explicit_drag = true;
  const int nv = m->nv;
  const std::unique_ptr<mjData, DataDelete> copy(mj_makeData(m));
  mj_copyData(copy.get(), m, d);
  mjData* c = copy.get();
  mju_zero(c->qvel, nv);
  mj_fwdPosition(m, c);
  Eigen::MatrixXd mass(nv, nv);
  mj_fullM(m, mass.data(), c->qM);  // symmetric: row or column major alike
  const std::vector<double> drag_values = DragMatrix(m, d);
  const Eigen::MatrixXd drag =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          drag_values.data(), nv, nv);
  const double drag_rate = LargestRate(drag, mass);
  step.drag_relaxation_s = drag_rate > 0.0 ? 1.0 / drag_rate : INFINITY;
  step.resolving_timestep_s =
      std::min(step.timestep_s, kMaxStepPerDragRelaxation * step.drag_relaxation_s);
  return step;
}

StepResolution WithSwimStepError(StepResolution step, double peak_tip_speed_mm_s,
                                 double body_length_mm, double mean_speed_mm_s) {
  if (!step.explicit_drag || mean_speed_mm_s == 0.0 || !(body_length_mm > 0.0)) return step;
  step.swim_error = kSwimStepErrorConstant * step.timestep_s * peak_tip_speed_mm_s *
                    peak_tip_speed_mm_s / (kTwoPi * body_length_mm * std::abs(mean_speed_mm_s));
  if (step.swim_error > kMaxSwimStepError) {
    // e is first order in h.
    step.resolving_timestep_s = std::min(step.resolving_timestep_s,
                                         step.timestep_s * kMaxSwimStepError / step.swim_error);
  }
  return step;
}

std::vector<std::string> StepResolutionWarnings(const StepResolution& step,
                                                double controller_rate_Hz) {
  if (step.Resolved()) return {};
  double use_s = step.resolving_timestep_s;
  if (controller_rate_Hz > 0.0) {
    // A whole number of steps per controller sample (printed to 10 digits,
    // which the run's check of the step takes as whole).
    use_s = 1.0 / (controller_rate_Hz * std::ceil(1.0 / (controller_rate_Hz * use_s) - 1e-9));
  }
  std::ostringstream text;
  text << std::setprecision(3) << "the time step " << Milliseconds(step.timestep_s)
       << " may put the swim off by about " << 100.0 * step.swim_error
       << " % (the inertial step takes the drag at the step's start; estimated as "
       << kSwimStepErrorConstant
       << " h v_tip^2 / (2 pi L U), above the error of every run measured) and steps "
       << step.timestep_s / step.drag_relaxation_s << " drag relaxations m / (xi L) = "
       << Milliseconds(step.drag_relaxation_s) << " (above " << kMaxStepPerDragRelaxation
       << " is not resolved); for the swim within " << 100.0 * kMaxSwimStepError
       << " % take timestep_s = " << std::setprecision(10) << use_s
       << " or dynamics = \"stokes\" (no inertia, drag at the step's midpoint, any step)";
  return {text.str()};
}

}  // namespace ipmc
