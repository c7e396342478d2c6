#include "sim/core/step_resolution.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <complex>
#include <iomanip>
#include <memory>
#include <sstream>

#include "plugin/coupling.h"

namespace ipmc {
namespace {

constexpr double kTwoPi = 6.283185307179586;
// The most halvings the search for a resolving step tries.
constexpr int kMaxHalvings = 30;

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

// The linearised body at its rest shape.
struct LinearBody {
  // damping: the step's (dof_damping, c_eff where the coupling gave it,
  // plugin/dynamics/step_model.h); physical_damping: the hinges' own c.
  Eigen::MatrixXd mass, drag, stiffness, damping, physical_damping;
  std::vector<int> hinges;  // the dofs of hinge joints
};

// || H_h - H ||_F / || H ||_F over the hinges (the header's formulas).
double ResponseError(const LinearBody& body, double h, double omega) {
  using Complex = std::complex<double>;
  using ComplexMatrix = Eigen::MatrixXcd;
  const Eigen::Index n = body.mass.rows();
  const Complex i_omega(0.0, omega);
  const ComplexMatrix exact_system =
      (body.stiffness - omega * omega * body.mass).cast<Complex>() +
      i_omega * (body.physical_damping + body.drag).cast<Complex>();
  const Eigen::MatrixXd a_inv = (body.mass + h * body.damping).inverse();
  // x' = Phi x + Gamma f, x = [q; v].
  Eigen::MatrixXd phi(2 * n, 2 * n), gamma(2 * n, n);
  const Eigen::MatrixXd v_from_q = -h * a_inv * body.stiffness;
  const Eigen::MatrixXd v_from_v = a_inv * (body.mass - h * body.drag);
  phi << Eigen::MatrixXd::Identity(n, n) + h * v_from_q, h * v_from_v, v_from_q, v_from_v;
  gamma << h * h * a_inv, h * a_inv;
  const Complex z = std::exp(Complex(0.0, omega * h));
  const ComplexMatrix stepped_system = z * ComplexMatrix::Identity(2 * n, 2 * n) - phi.cast<Complex>();
  ComplexMatrix forcing = ComplexMatrix::Zero(n, body.hinges.size());
  for (std::size_t c = 0; c < body.hinges.size(); ++c) forcing(body.hinges[c], c) = 1.0;
  const ComplexMatrix exact = exact_system.partialPivLu().solve(forcing);
  const ComplexMatrix stepped =
      stepped_system.partialPivLu().solve(gamma.cast<Complex>() * forcing).topRows(n);
  double difference = 0.0, size = 0.0;
  for (int hinge : body.hinges) {
    difference += (stepped.row(hinge) - exact.row(hinge)).squaredNorm();
    size += exact.row(hinge).squaredNorm();
  }
  return size > 0.0 ? std::sqrt(difference / size) : 0.0;
}

std::string Milliseconds(double t_s) {
  std::ostringstream text;
  text << std::setprecision(3) << t_s * 1e3 << " ms";
  return text.str();
}

}  // namespace

bool StepResolution::Resolved() const {
  return !explicit_drag || (response_error <= kMaxResponseError &&
                            timestep_s <= kMaxStepPerDragRelaxation * drag_relaxation_s);
}

StepResolution MeasureStepResolution(const mjModel* m, const mjData* d, double frequency_Hz) {
  StepResolution step;
  step.timestep_s = step.resolving_timestep_s = m->opt.timestep;
  step.frequency_Hz = frequency_Hz;
  const CouplingContext* coupling = FindCoupling(d);
  if (coupling == nullptr || !coupling->fluid || coupling->dynamics != Dynamics::kInertial ||
      !(frequency_Hz > 0.0)) {
    return step;
  }
  step.explicit_drag = true;
  const int nv = m->nv;
  const std::unique_ptr<mjData, DataDelete> copy(mj_makeData(m));
  mj_copyData(copy.get(), m, d);
  mjData* c = copy.get();
  mju_zero(c->qvel, nv);
  mj_fwdPosition(m, c);
  LinearBody body;
  body.mass.resize(nv, nv);
  mj_fullM(m, body.mass.data(), c->qM);  // symmetric: row or column major alike
  body.drag.resize(nv, nv);
  body.stiffness = body.damping = Eigen::MatrixXd::Zero(nv, nv);
  const std::vector<double>* physical =
      coupling->actuators ? &coupling->actuators->PhysicalDamping() : nullptr;
  if (physical != nullptr && static_cast<int>(physical->size()) != nv) physical = nullptr;
  body.physical_damping = body.damping;
  for (int j = 0; j < nv; ++j) {
    mju_zero(c->qvel, nv);
    c->qvel[j] = 1.0;
    mj_comVel(m, c);
    mju_zero(c->qfrc_passive, nv);
    coupling->fluid->Apply(m, c);
    for (int i = 0; i < nv; ++i) body.drag(i, j) = -c->qfrc_passive[i];
    body.damping(j, j) = coupling->step.model->dof_damping[j];
    body.physical_damping(j, j) = physical != nullptr ? (*physical)[j] : m->dof_damping[j];
    const int joint = m->dof_jntid[j];
    if (m->jnt_type[joint] == mjJNT_HINGE) {
      body.stiffness(j, j) = m->jnt_stiffness[joint];
      body.hinges.push_back(j);
    }
  }
  body.drag = 0.5 * (body.drag + body.drag.transpose());
  const double drag_rate = LargestRate(body.drag, body.mass);
  step.drag_relaxation_s = drag_rate > 0.0 ? 1.0 / drag_rate : INFINITY;
  step.hinge_rate_rad_s = std::sqrt(LargestRate(body.stiffness, body.mass));
  if (body.hinges.empty()) return step;
  const double omega = kTwoPi * frequency_Hz;
  step.response_error = ResponseError(body, step.timestep_s, omega);
  double h = step.timestep_s;
  const double max_step_s = kMaxStepPerDragRelaxation * step.drag_relaxation_s;
  for (int j = 0; j < kMaxHalvings &&
                  (ResponseError(body, h, omega) > kMaxResponseError || h > max_step_s);
       ++j) {
    h /= 2.0;
  }
  step.resolving_timestep_s = h;
  return step;
}

std::vector<std::string> StepResolutionWarnings(const StepResolution& step,
                                                double controller_rate_Hz) {
  if (step.Resolved()) return {};
  double use_s = step.resolving_timestep_s;
  if (controller_rate_Hz > 0.0) {
    // A whole number of steps per controller sample.
    use_s = 1.0 / (controller_rate_Hz * std::ceil(1.0 / (controller_rate_Hz * use_s) - 1e-9));
  }
  std::ostringstream text;
  text << std::setprecision(3) << "the time step " << Milliseconds(step.timestep_s)
       << " does not resolve what the inertial dynamics integrates explicitly: its response "
          "to the hinges' moments at the wave's "
       << step.frequency_Hz << " Hz is " << step.response_error << " off (above "
       << kMaxResponseError << "), h / tau = " << step.timestep_s / step.drag_relaxation_s
       << " of the drag relaxation m / (xi L) = " << Milliseconds(step.drag_relaxation_s)
       << " (above " << kMaxStepPerDragRelaxation
       << " is not resolved), so the swim may be off by more than 1 %; take timestep_s = "
       << use_s
       << " or dynamics = \"stokes\" (no inertia, stiffness and drag implicit, any step)";
  return {text.str()};
}

}  // namespace ipmc
