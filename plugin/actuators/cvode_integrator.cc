#include "plugin/actuators/cvode_integrator.h"

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_band.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_band.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "plugin/actuators/serial_kernels.h"
#include "plugin/actuators/shifted_schur.h"

namespace ipmc {
namespace {

// Newton convergence coefficient for an exact linear solve (CreateCvode).
constexpr double kExactNewtonConvCoef = 1e6;
// The smooth form restarts at the first change in each window of absolute
// time this long, which bounds P and Q and so the cancellation in
// x = eta + B P + A B Q (header, "Stepping").
constexpr double kRebase_s = 0.1;
// A stop time CVODE never reaches: no stop.
constexpr double kNoStop_s = std::numeric_limits<double>::max();

std::string FlagName(int flag) {
  char* name = CVodeGetReturnFlagName(flag);
  std::string out = name != nullptr ? name : "unknown flag";
  std::free(name);
  return out;
}

}  // namespace

CvodeIntegrator::CvodeIntegrator(const StackedLinearSystem& system, const CvodeOptions& options)
    : LinearSystemIntegrator(system.States()), system_(system), options_(options) {
  FactorBlocks();
  const int n = system_.States();
  const std::size_t links = system_.Blocks().size();
  held_input_V_.assign(links, 0.0);
  forcing_ = Eigen::VectorXd::Zero(n);
  eta_ = Eigen::VectorXd::Zero(n);
  segment_integral_Vs_.assign(links, 0.0);
  segment_double_integral_Vs2_.assign(links, 0.0);
  segment_voltage_V_ = held_input_V_;
  derivative_ = Eigen::VectorXd::Zero(n);
  second_derivative_ = Eigen::VectorXd::Zero(n);
  CreateCvode();
}

CvodeIntegrator::~CvodeIntegrator() = default;

// The Schur forms, the smooth form's input terms and the cap on the first
// step, from the links' blocks.
void CvodeIntegrator::FactorBlocks() {
  const std::vector<LinkBlock>& blocks = system_.Blocks();
  factors_.resize(blocks.size());
  int largest_block = 0;
  for (std::size_t q = 0; q < blocks.size(); ++q) {
    const LinkBlock& block = blocks[q];
    BlockFactors& factors = factors_[q];
    largest_block = std::max(largest_block, block.size);
    if (block.size == 0) continue;
    if (IsQuasiLowerTriangular(block.a)) {
      factors.reversed = true;
      factors.schur_t_rows = block.a.reverse().transpose();  // P a P, by rows
      continue;
    }
    const Eigen::RealSchur<Eigen::MatrixXd> schur(block.a);
    if (schur.info() != Eigen::Success) {
      throw std::invalid_argument("ipmc actuator: link " + std::to_string(q + 1) +
                                  ": real Schur decomposition of a did not converge");
    }
    factors.schur_q = schur.matrixU();
    factors.schur_t_rows = schur.matrixT().transpose();
  }
  schur_work_ = Eigen::VectorXd::Zero(largest_block);
  double fastest_rate = 0.0;
  for (std::size_t q = 0; q < blocks.size(); ++q) {
    const LinkBlock& block = blocks[q];
    factors_[q].ab = block.a * block.b;
    factors_[q].aab = block.a * factors_[q].ab;
    if (block.size == 0) continue;
    const Eigen::VectorXcd eigenvalues =
        Eigen::EigenSolver<Eigen::MatrixXd>(block.a, false).eigenvalues();
    fastest_rate = std::max(fastest_rate, eigenvalues.cwiseAbs().maxCoeff());
  }
  // 0 if every a is zero (InitialStep_s then leaves the first step to CVODE).
  initial_step_cap_s_ =
      fastest_rate > 0.0 && std::isfinite(fastest_rate) ? 1.0 / fastest_rate : 0.0;
}

SUNLinearSolver_Type CvodeIntegrator::SchurType(SUNLinearSolver /*solver*/) {
  return SUNLINEARSOLVER_MATRIX_EMBEDDED;
}

// x = (I - gamma A)^-1 r block by block, x_q = Q (I - gamma T)^-1 Q^T r_q,
// with CVODE's current gamma.
int CvodeIntegrator::SchurSolve(SUNLinearSolver solver, SUNMatrix /*unused*/, N_Vector x,
                                N_Vector r, realtype /*tol*/) {
  auto* self = static_cast<CvodeIntegrator*>(solver->content);
  realtype gamma = 0;
  if (CVodeGetCurrentGamma(self->cvode_.get(), &gamma) != CV_SUCCESS) {
    return SUNLS_MEM_NULL;
  }
  const double* r_all = N_VGetArrayPointer(r);
  double* x_all = N_VGetArrayPointer(x);
  double* work = self->schur_work_.data();
  const std::vector<LinkBlock>& blocks = self->system_.Blocks();
  for (std::size_t q = 0; q < blocks.size(); ++q) {
    const LinkBlock& block = blocks[q];
    const BlockFactors& factors = self->factors_[q];
    const double* schur_q = factors.reversed ? nullptr : factors.schur_q.data();
    if (!SolveShiftedSchur(schur_q, factors.schur_t_rows.data(), block.size, gamma,
                           r_all + block.first_state, x_all + block.first_state, work)) {
      return SUNLS_LUFACT_FAIL;  // recoverable: CVODE retries a smaller step
    }
  }
  return SUNLS_SUCCESS;
}

int CvodeIntegrator::SchurFree(SUNLinearSolver solver) {
  if (solver == nullptr) return SUNLS_SUCCESS;
  solver->content = nullptr;  // owned by the integrator, not by SUNDIALS
  SUNLinSolFreeEmpty(solver);
  return SUNLS_SUCCESS;
}

SUNLinearSolver CvodeIntegrator::NewSchurSolver() {
  SUNLinearSolver solver = SUNLinSolNewEmpty(context_.get());
  if (solver == nullptr) return nullptr;
  solver->ops->gettype = SchurType;
  solver->ops->solve = SchurSolve;
  solver->ops->free = SchurFree;
  solver->content = this;
  return solver;
}

// d eta / dt: A eta + B u (plain) or A eta + A^2 B Q(t) (smooth).
int CvodeIntegrator::Rhs(realtype t, N_Vector x, N_Vector xdot, void* user_data) {
  const auto* self = static_cast<const CvodeIntegrator*>(user_data);
  self->Derivative(t, N_VGetArrayPointer(x), N_VGetArrayPointer(xdot));
  return 0;
}

void CvodeIntegrator::UpdateForcing(const std::vector<double>& held_input_V) {
  const std::vector<LinkBlock>& blocks = system_.Blocks();
  for (std::size_t q = 0; q < blocks.size(); ++q) {
    if (held_input_V[q] == held_input_V_[q]) continue;
    held_input_V_[q] = held_input_V[q];
    forcing_.segment(blocks[q].first_state, blocks[q].size) = blocks[q].b * held_input_V[q];
  }
}

void CvodeIntegrator::HeldInputChanged(const std::vector<double>& held_input_V) {
  UpdateForcing(held_input_V);
  input_changed_ = true;
}

void CvodeIntegrator::StartAfresh(Start start) {
  pending_restart_ =
      start == Start::kFromRest ? PendingRestart::kPlain : PendingRestart::kSmooth;
  input_changed_ = false;  // the restart takes the held input as it is
}

void CvodeIntegrator::VoltageIntegrals(double t_s, int link, double* integral_Vs,
                                       double* double_integral_Vs2) const {
  const double tau = t_s - segment_s_;
  const double u = segment_voltage_V_[link];
  *integral_Vs = segment_integral_Vs_[link] + u * tau;
  *double_integral_Vs2 =
      segment_double_integral_Vs2_[link] + (segment_integral_Vs_[link] + 0.5 * u * tau) * tau;
}

void CvodeIntegrator::Derivative(double t_s, const double* in, double* out) const {
  if (!smooth_) {
    system_.ApplyA(in, forcing_.data(), out);
    return;
  }
  system_.ApplyA(in, nullptr, out);
  const std::vector<LinkBlock>& blocks = system_.Blocks();
  for (std::size_t q = 0; q < blocks.size(); ++q) {
    double integral_Vs = 0, double_integral_Vs2 = 0;
    VoltageIntegrals(t_s, static_cast<int>(q), &integral_Vs, &double_integral_Vs2);
    const Eigen::VectorXd& aab = factors_[q].aab;
    for (int i = 0; i < blocks[q].size; ++i) {
      out[blocks[q].first_state + i] += aab[i] * double_integral_Vs2;
    }
  }
}

void CvodeIntegrator::StateFromEta(double t_s) {
  state_ = eta_;
  if (!smooth_) return;
  const std::vector<LinkBlock>& blocks = system_.Blocks();
  for (std::size_t q = 0; q < blocks.size(); ++q) {
    double integral_Vs = 0, double_integral_Vs2 = 0;
    VoltageIntegrals(t_s, static_cast<int>(q), &integral_Vs, &double_integral_Vs2);
    const LinkBlock& block = blocks[q];
    state_.segment(block.first_state, block.size) +=
        block.b * integral_Vs + factors_[q].ab * double_integral_Vs2;
  }
}

// J = df/dx = A, constant: copied into the dense or band matrix.
int CvodeIntegrator::Jacobian(realtype /*t*/, N_Vector /*x*/, N_Vector /*fx*/, SUNMatrix jac,
                              void* user_data, N_Vector /*tmp1*/, N_Vector /*tmp2*/,
                              N_Vector /*tmp3*/) {
  const auto* self = static_cast<const CvodeIntegrator*>(user_data);
  const Eigen::MatrixXd& a = self->system_.StackedA();
  const int n = self->system_.States();
  if (SUNMatGetID(jac) == SUNMATRIX_DENSE) {
    std::memcpy(SUNDenseMatrix_Data(jac), a.data(),
                sizeof(double) * static_cast<std::size_t>(n) * n);
    return 0;
  }
  if (SUNMatZero(jac) != 0) return -1;
  for (int j = 0; j < n; ++j) {
    const int i_begin = std::max(0, j - self->system_.UpperBandwidth());
    const int i_end = std::min(n - 1, j + self->system_.LowerBandwidth());
    for (int i = i_begin; i <= i_end; ++i) SM_ELEMENT_B(jac, i, j) = a(i, j);
  }
  return 0;
}

// Keeps CVODE's last message for the exception instead of printing it.
void CvodeIntegrator::CaptureMessage(int /*error_code*/, const char* /*module*/,
                                     const char* function, char* msg, void* user_data) {
  auto* self = static_cast<CvodeIntegrator*>(user_data);
  self->last_cvode_message_ = std::string(function) + ": " + msg;
}

void CvodeIntegrator::Check(int flag, const char* call) const {
  if (flag >= 0) return;
  std::ostringstream out;
  out << "ipmc actuator: " << call << " failed at t = " << time_s_ << " s: " << FlagName(flag);
  if (!last_cvode_message_.empty()) out << " (" << last_cvode_message_ << ")";
  throw std::runtime_error(out.str());
}

void CvodeIntegrator::ThrowSolverFailure(int flag) {
  realtype t_reached = time_s_;
  if (CVodeGetCurrentTime(cvode_.get(), &t_reached) != CV_SUCCESS) {
    t_reached = time_s_;
  }
  // Name the link whose states carry the largest weighted local error.
  const std::vector<LinkBlock>& blocks = system_.Blocks();
  sundials_handles::VectorPtr errors(N_VClone(y_vector_.get()));
  sundials_handles::VectorPtr weights(N_VClone(y_vector_.get()));
  int worst_link = -1;
  if (errors && weights && CVodeGetEstLocalErrors(cvode_.get(), errors.get()) == CV_SUCCESS &&
      CVodeGetErrWeights(cvode_.get(), weights.get()) == CV_SUCCESS) {
    const double* e = N_VGetArrayPointer(errors.get());
    const double* w = N_VGetArrayPointer(weights.get());
    double worst = -1;
    for (std::size_t q = 0; q < blocks.size(); ++q) {
      const int end = blocks[q].first_state + blocks[q].size;
      for (int i = blocks[q].first_state; i < end; ++i) {
        const double weighted = std::abs(e[i] * w[i]);
        if (weighted > worst) {
          worst = weighted;
          worst_link = static_cast<int>(q) + 1;
        }
      }
    }
  }
  std::ostringstream out;
  out << "ipmc actuator: CVode failed at t = " << t_reached << " s (";
  if (worst_link > 0) {
    out << "link " << worst_link << " of " << blocks.size() << " has the largest local error";
  } else {
    out << blocks.size() << " links";
  }
  out << "): " << FlagName(flag);
  if (!last_cvode_message_.empty()) out << ": " << last_cvode_message_;
  throw std::runtime_error(out.str());
}

void CvodeIntegrator::CreateLinearSolver() {
  const int n = system_.States();
  switch (options_.linear_solver) {
    case CvodeLinearSolver::kBlockSchur:
      linear_solver_.reset(NewSchurSolver());
      break;
    case CvodeLinearSolver::kDense:
      matrix_.reset(SUNDenseMatrix(n, n, context_.get()));
      if (!matrix_) break;
      linear_solver_.reset(SUNLinSol_Dense(y_vector_.get(), matrix_.get(), context_.get()));
      break;
    case CvodeLinearSolver::kBand:
      matrix_.reset(SUNBandMatrix(n, system_.UpperBandwidth(), system_.LowerBandwidth(),
                                  context_.get()));
      if (!matrix_) break;
      linear_solver_.reset(SUNLinSol_Band(y_vector_.get(), matrix_.get(), context_.get()));
      break;
  }
  if (!linear_solver_) {
    throw std::runtime_error("ipmc actuator: linear solver creation failed");
  }
}

void CvodeIntegrator::CreateCvode() {
  SUNContext raw_context = nullptr;
  if (SUNContext_Create(nullptr, &raw_context) != 0 || raw_context == nullptr) {
    throw std::runtime_error("ipmc actuator: SUNContext_Create failed");
  }
  context_.reset(raw_context);
  y_vector_.reset(N_VMake_Serial(system_.States(), eta_.data(), context_.get()));
  if (!y_vector_) throw std::runtime_error("ipmc actuator: N_VMake_Serial failed");
  serial_kernels::Install(y_vector_.get());
  CreateLinearSolver();
  cvode_.reset(CVodeCreate(CV_BDF, context_.get()));
  if (!cvode_) throw std::runtime_error("ipmc actuator: CVodeCreate failed");
  void* mem = cvode_.get();
  Check(CVodeSetErrHandlerFn(mem, CaptureMessage, this), "CVodeSetErrHandlerFn");
  Check(CVodeInit(mem, Rhs, time_s_, y_vector_.get()), "CVodeInit");
  Check(CVodeSetUserData(mem, this), "CVodeSetUserData");
  Check(CVodeSStolerances(mem, options_.rel_tol, options_.abs_tol_mm), "CVodeSStolerances");
  Check(CVodeSetMaxNumSteps(mem, options_.max_steps), "CVodeSetMaxNumSteps");
  Check(CVodeSetLinearSolver(mem, linear_solver_.get(), matrix_.get()), "CVodeSetLinearSolver");
  if (matrix_) Check(CVodeSetJacFn(mem, Jacobian), "CVodeSetJacFn");
  if (options_.linear_solver == CvodeLinearSolver::kBlockSchur) {
    // The ODE is linear and the Schur solve uses CVODE's current gamma, so
    // the first Newton correction solves each step's corrector equation to
    // rounding. CVODE's convergence test does not know it: from a restart
    // its rate estimate starts at 1 and it asks for a second correction
    // (a right-hand side, a solve and norms) on the first steps after
    // every voltage change. A coefficient far above CVODE's 0.1 accepts
    // the first correction; CVODE's error test is unchanged.
    Check(CVodeSetNonlinConvCoef(mem, kExactNewtonConvCoef), "CVodeSetNonlinConvCoef");
  }
}

// The order-1 step whose local error (h^2 / 2) eta'' has weighted RMS norm
// 1/4 (CVODE accepts a step at norm 1), with eta'' exact for the held
// input: A eta' (+ A^2 B P in the smooth form, where P = 0 at a restart),
// at most 1 / the fastest eigenvalue of A (the time over which the fastest
// mode moves by O(1); also taken when eta'' = 0) and at least 100 u |t|,
// u the unit roundoff. It depends only on the state, the voltages and the
// tolerances, as the rest of the integration from a restart does
// (Restart), and it spares the right-hand-side evaluations of CVODE's
// iterative estimate (cvHin) at every restart.
double CvodeIntegrator::InitialStep_s() {
  Derivative(time_s_, eta_.data(), derivative_.data());
  system_.ApplyA(derivative_.data(), nullptr, second_derivative_.data());
  const int n = system_.States();
  double sum_squares = 0.0;
  for (int i = 0; i < n; ++i) {
    const double weighted =
        second_derivative_[i] / (options_.rel_tol * std::abs(eta_[i]) + options_.abs_tol_mm);
    sum_squares += weighted * weighted;
  }
  const double norm = std::sqrt(sum_squares / n);
  const double lower_s = 100.0 * std::numeric_limits<double>::epsilon() * std::abs(time_s_);
  // (h^2 / 2) norm = 1/4
  if (!(initial_step_cap_s_ > 0.0)) return 0.0;  // A = 0: CVODE's own estimate
  const double step_s = norm > 0.0 ? std::sqrt(0.5 / norm) : initial_step_cap_s_;
  return std::clamp(step_s, std::min(lower_s, initial_step_cap_s_), initial_step_cap_s_);
}

void CvodeIntegrator::RestartAt(bool smooth_form) {
  void* mem = cvode_.get();
  long steps = 0;
  Check(CVodeGetNumSteps(mem, &steps), "CVodeGetNumSteps");
  steps_before_reinit_ += steps;
  smooth_ = smooth_form;
  base_s_ = segment_s_ = time_s_;
  segment_integral_Vs_.assign(held_input_V_.size(), 0.0);
  segment_double_integral_Vs2_.assign(held_input_V_.size(), 0.0);
  segment_voltage_V_ = held_input_V_;
  eta_ = state_;  // P = Q = 0 at the restart
  // From x(time_s_): no step taken with the old input beyond time_s_ is used.
  Check(CVodeReInit(mem, time_s_, y_vector_.get()), "CVodeReInit");
  Check(CVodeSetInitStep(mem, InitialStep_s()), "CVodeSetInitStep");
  Check(CVodeSetStopTime(mem, kNoStop_s), "CVodeSetStopTime");
  ++reinitialisations_;
}

void CvodeIntegrator::SetSmoothStop(double period_s) {
  double stop_s = segment_s_ + kRebase_s;
  if (period_s > 0.0) stop_s = std::min(stop_s, time_s_ + period_s);
  Check(CVodeSetStopTime(cvode_.get(), stop_s), "CVodeSetStopTime");
}

void CvodeIntegrator::OnVoltageChange() {
  realtype t_cvode = time_s_;
  Check(CVodeGetCurrentTime(cvode_.get(), &t_cvode), "CVodeGetCurrentTime");
  const double period_s = std::isfinite(last_change_s_) ? time_s_ - last_change_s_ : 0.0;
  last_change_s_ = time_s_;
  period_known_ = period_s > 0.0;
  const bool stopped_here = std::abs(t_cvode - time_s_) <= UnresolvableInterval_s(t_cvode, time_s_);
  // Rebase at the first change in each kRebase_s window of absolute time,
  // the same instants in every integrator that sees the same changes.
  const bool same_window = std::floor(time_s_ / kRebase_s) == std::floor(base_s_ / kRebase_s);
  if (smooth_ && stopped_here && same_window) {
    // Continue: P and Q stay continuous, the new voltages hold from here.
    for (std::size_t q = 0; q < held_input_V_.size(); ++q) {
      double integral_Vs = 0, double_integral_Vs2 = 0;
      VoltageIntegrals(t_cvode, static_cast<int>(q), &integral_Vs, &double_integral_Vs2);
      segment_integral_Vs_[q] = integral_Vs;
      segment_double_integral_Vs2_[q] = double_integral_Vs2;
    }
    segment_s_ = t_cvode;
    segment_voltage_V_ = held_input_V_;
  } else {
    // CVODE went past the change (it did not know when it would come), or
    // this is the first change of a kRebase_s window: start again here, which is
    // gentler than a plain restart (eta has no kink at a restart).
    RestartAt(true);
  }
  SetSmoothStop(period_s);
}

void CvodeIntegrator::Integrate(double t_s) {
  last_cvode_message_.clear();
  realtype t_returned = time_s_;
  for (;;) {
    const int flag = CVode(cvode_.get(), t_s, y_vector_.get(), &t_returned, CV_NORMAL);
    if (flag < 0) {
      // CVODE left the solution of its last successful step in eta_:
      // continue from there (after a restart) if the caller retries.
      time_s_ = std::max(time_s_, static_cast<double>(t_returned));
      StateFromEta(t_returned);
      pending_restart_ = PendingRestart::kPlain;
      ThrowSolverFailure(flag);
    }
    // At a stop CVODE drops the stop time. A stop where the voltages are
    // expected to change next is followed, unless they do change there
    // (OnVoltageChange sets a new stop), by one where a hold ends: there
    // the voltages have held for kRebase_s, P and Q would only grow, and
    // the plain form goes on.
    if (flag == CV_TSTOP_RETURN && smooth_) {
      const double hold_end_s = segment_s_ + kRebase_s;
      if (t_returned >= hold_end_s - UnresolvableInterval_s(t_returned, hold_end_s)) {
        time_s_ = t_returned;
        StateFromEta(t_returned);
        RestartAt(false);
      } else {
        Check(CVodeSetStopTime(cvode_.get(), hold_end_s), "CVodeSetStopTime");
      }
    }
    if (flag != CV_TSTOP_RETURN || t_s - t_returned <= UnresolvableInterval_s(t_s, t_returned)) {
      break;
    }
  }
  StateFromEta(t_returned);
  time_s_ = t_s;
}

void CvodeIntegrator::Advance(double t1_s, const std::vector<double>& held_input_V) {
  UpdateForcing(held_input_V);
  if (pending_restart_ != PendingRestart::kNone) {
    // The restart takes any new voltages; a change at this instant is the
    // first the integrator knows of.
    last_change_s_ = input_changed_ ? time_s_ : std::numeric_limits<double>::quiet_NaN();
    // A state at rest restarts in the plain form whichever restart asked
    // for it, so that an integrator reset (or new) and then saved or
    // restored steps as a new one does.
    const bool smooth_form =
        pending_restart_ == PendingRestart::kSmooth && (state_.array() != 0.0).any();
    RestartAt(smooth_form);
    period_known_ = false;
  } else if (input_changed_) {
    OnVoltageChange();
  }
  pending_restart_ = PendingRestart::kNone;
  input_changed_ = false;
  if (smooth_ && !period_known_) {
    Check(CVodeSetStopTime(cvode_.get(), std::min(t1_s, segment_s_ + kRebase_s)),
          "CVodeSetStopTime");
  }
  Integrate(t1_s);
}

long CvodeIntegrator::InternalSteps() const {
  long steps = 0;
  Check(CVodeGetNumSteps(cvode_.get(), &steps), "CVodeGetNumSteps");
  return steps_before_reinit_ + steps;
}

}  // namespace ipmc
