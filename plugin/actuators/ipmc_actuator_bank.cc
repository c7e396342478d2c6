#include "plugin/actuators/ipmc_actuator_bank.h"

#include <cvode/cvode.h>
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
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "plugin/actuators/serial_kernels.h"
#include "plugin/actuators/shifted_schur.h"
#include "plugin/actuators/sundials_handles.h"
#include "plugin/actuators/zero_order_hold.h"

namespace ipmc {
namespace {

using sundials_handles::ContextPtr;
using sundials_handles::CvodePtr;
using sundials_handles::LinearSolverPtr;
using sundials_handles::MatrixPtr;
using sundials_handles::VectorPtr;

struct Block {
  int offset = 0;  // first state in x
  int size = 0;
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
  Eigen::VectorXd ab, aab;  // a b and a^2 b (the smooth form's input terms)
  Eigen::RowVectorXd c;
  double d = 0;
  // Real Schur form a = schur_q * schur_t * schur_q^T (kBlockSchur only);
  // schur_t_rows holds T by rows (the transpose, column-major), the order
  // in which the back substitution reads it. A block whose a is already
  // quasi-lower-triangular (the Oustaloup cascades of G1: each section
  // driven by the ones before it) needs no rotation: T = P a P with P the
  // reversal of the states, and schur_q stays empty.
  Eigen::MatrixXd schur_q;
  Eigen::MatrixXd schur_t_rows;
  bool reversed = false;  // Q = P instead of schur_q
};

// Newton convergence coefficient for an exact linear solve (InitCvode).
constexpr double kExactNewtonConvCoef = 1e6;
// The smooth form restarts at the first change in each window of absolute
// time this long, which bounds P and Q and so the cancellation in
// x = eta + B P + A B Q (header, "Stepping").
constexpr double kRebase_s = 0.1;
// A stop time CVODE never reaches: no stop.
constexpr double kNoStop_s = std::numeric_limits<double>::max();

// A time difference CVODE cannot resolve: a few ulps of t.
double Unresolvable_s(double a_s, double b_s) {
  return 8.0 * std::numeric_limits<double>::epsilon() *
         std::max({1.0, std::abs(a_s), std::abs(b_s)});
}

std::string FlagName(int flag) {
  char* name = CVodeGetReturnFlagName(flag);
  std::string out = name != nullptr ? name : "unknown flag";
  std::free(name);
  return out;
}

}  // namespace

struct IpmcActuatorBank::Impl {
  std::vector<Block> blocks;
  int states = 0;
  Eigen::MatrixXd jacobian;  // block-diagonal A, column-major like SUNDIALS
  // out = A in + add (add may be null), row by row: row i of A holds its
  // entries from column a_first[i] to its last nonzero, stored one after
  // the other from a_value[a_start[i]] (the cascades' A is lower
  // triangular, so a row is a run of columns with few zeros in it).
  void ApplyA(const double* in, const double* add, double* out) const;
  std::vector<int> a_start, a_first;
  std::vector<double> a_value;
  Eigen::VectorXd forcing;  // B u for the held u (plain form)
  Eigen::VectorXd state;    // x at time_s
  // What CVODE integrates (header, "Stepping"); y_vector wraps its storage.
  // The plain form: eta = x. The smooth form: eta = x - B P(t) - A B Q(t)
  // with P and Q the first and second integrals of u since the last
  // restart, base_s; the current voltages hold from segment_s, where
  // link q's voltage integrals were segment_integral_Vs[q] and
  // segment_double_integral_Vs2[q].
  Eigen::VectorXd eta;
  bool smooth = false;
  double base_s = 0, segment_s = 0;
  std::vector<double> segment_integral_Vs, segment_double_integral_Vs2, segment_voltage_V;
  std::vector<double> voltage_V;
  double time_s = 0;
  // A restart due at the next AdvanceTo, and in which form: the plain one
  // from rest (creation, Reset, a failure), the smooth one from a state
  // set or saved (SetState, Restart: the form a run of changes goes on in,
  // and the same for the bank saved and the one restored).
  enum class PendingRestart { kNone, kPlain, kSmooth };
  PendingRestart pending_restart = PendingRestart::kNone;
  bool voltage_changed = false;  // SetVoltages changed a value at time_s
  // The time of the last voltage change since the last restart (NaN: none).
  double last_change_s = std::numeric_limits<double>::quiet_NaN();
  // The smooth form expects the next change a period after the last; with
  // no period seen since its restart it stops CVODE at every AdvanceTo, so
  // that CVODE is at the change, wherever it comes.
  bool period_known = false;
  double initial_step_cap_s = 0;  // 1 / the fastest eigenvalue of A
  long steps_before_reinit = 0;
  long reinitialisations = 0;
  int lower_bandwidth = 0;
  int upper_bandwidth = 0;
  CvodeOptions options;
  std::string last_cvode_message;
  Eigen::VectorXd schur_work;                     // Q^T r of one block
  Eigen::VectorXd derivative, second_derivative;  // eta' and eta'' at a restart

  // kExact: the exact integration, and no CVODE.
  std::unique_ptr<ZeroOrderHold> exact;

  ContextPtr context;
  VectorPtr y_vector;
  MatrixPtr matrix;
  LinearSolverPtr linear_solver;
  CvodePtr cvode;

  void Check(int flag, const char* call) const;
  // P_q(t) and Q_q(t) of link q in the current segment: the integral of
  // its voltage [V s] and the integral of that [V s^2].
  void VoltageIntegrals(double t_s, int link, double* integral_Vs,
                        double* double_integral_Vs2) const;
  // out = d eta / dt at t for eta = in, in the current form.
  void Derivative(double t_s, const double* in, double* out) const;
  // x at t from eta at t.
  void StateFromEta(double t_s);
  // CVODE's first step from a restart at time_s.
  double InitialStep_s();
  // Restarts CVODE at time_s from state, in the smooth or the plain form.
  void RestartAt(bool smooth_form);
  // The stop time of the smooth form: the next change if it keeps the
  // period, or where a hold would end, whichever comes first.
  void SetSmoothStop(double period_s);
  // The voltages changed at time_s: continue smoothly or restart.
  void OnVoltageChange();
  // Integrates to t_s and sets time_s and state.
  void Integrate(double t_s);
  [[noreturn]] void ThrowSolverFailure(int flag);
  void InitCvode();

  // CVODE callbacks; user_data is the Impl.
  static int Rhs(realtype t, N_Vector x, N_Vector xdot, void* user_data);
  static int Jacobian(realtype t, N_Vector x, N_Vector fx, SUNMatrix jac, void* user_data,
                      N_Vector tmp1, N_Vector tmp2, N_Vector tmp3);
  static void CaptureMessage(int error_code, const char* module, const char* function, char* msg,
                             void* user_data);
  // Matrix-embedded linear solver (kBlockSchur); content is the Impl.
  static SUNLinearSolver_Type SchurType(SUNLinearSolver solver);
  static int SchurSolve(SUNLinearSolver solver, SUNMatrix unused, N_Vector x, N_Vector r,
                        realtype tol);
  static int SchurFree(SUNLinearSolver solver);
  SUNLinearSolver NewSchurSolver();
};

SUNLinearSolver_Type IpmcActuatorBank::Impl::SchurType(SUNLinearSolver /*solver*/) {
  return SUNLINEARSOLVER_MATRIX_EMBEDDED;
}

// x = (I - gamma A)^-1 r block by block, x_q = Q (I - gamma T)^-1 Q^T r_q,
// with CVODE's current gamma.
int IpmcActuatorBank::Impl::SchurSolve(SUNLinearSolver solver, SUNMatrix /*unused*/, N_Vector x,
                                       N_Vector r, realtype /*tol*/) {
  auto* impl = static_cast<Impl*>(solver->content);
  realtype gamma = 0;
  if (CVodeGetCurrentGamma(impl->cvode.get(), &gamma) != CV_SUCCESS) {
    return SUNLS_MEM_NULL;
  }
  const double* r_all = N_VGetArrayPointer(r);
  double* x_all = N_VGetArrayPointer(x);
  double* work = impl->schur_work.data();
  for (const Block& block : impl->blocks) {
    const double* q = block.reversed ? nullptr : block.schur_q.data();
    if (!SolveShiftedSchur(q, block.schur_t_rows.data(), block.size, gamma, r_all + block.offset,
                           x_all + block.offset, work)) {
      return SUNLS_LUFACT_FAIL;  // recoverable: CVODE retries a smaller step
    }
  }
  return SUNLS_SUCCESS;
}

int IpmcActuatorBank::Impl::SchurFree(SUNLinearSolver solver) {
  if (solver == nullptr) return SUNLS_SUCCESS;
  solver->content = nullptr;  // owned by the bank, not by SUNDIALS
  SUNLinSolFreeEmpty(solver);
  return SUNLS_SUCCESS;
}

SUNLinearSolver IpmcActuatorBank::Impl::NewSchurSolver() {
  SUNLinearSolver solver = SUNLinSolNewEmpty(context.get());
  if (solver == nullptr) return nullptr;
  solver->ops->gettype = SchurType;
  solver->ops->solve = SchurSolve;
  solver->ops->free = SchurFree;
  solver->content = this;
  return solver;
}

// d eta / dt: A eta + B u (plain) or A eta + A^2 B Q(t) (smooth).
int IpmcActuatorBank::Impl::Rhs(realtype t, N_Vector x, N_Vector xdot, void* user_data) {
  const auto* impl = static_cast<const Impl*>(user_data);
  impl->Derivative(t, N_VGetArrayPointer(x), N_VGetArrayPointer(xdot));
  return 0;
}

void IpmcActuatorBank::Impl::VoltageIntegrals(double t_s, int link, double* integral_Vs,
                                              double* double_integral_Vs2) const {
  const double tau = t_s - segment_s;
  const double u = segment_voltage_V[link];
  *integral_Vs = segment_integral_Vs[link] + u * tau;
  *double_integral_Vs2 =
      segment_double_integral_Vs2[link] + (segment_integral_Vs[link] + 0.5 * u * tau) * tau;
}

void IpmcActuatorBank::Impl::Derivative(double t_s, const double* in, double* out) const {
  if (!smooth) {
    ApplyA(in, forcing.data(), out);
    return;
  }
  ApplyA(in, nullptr, out);
  for (std::size_t q = 0; q < blocks.size(); ++q) {
    double integral_Vs = 0, double_integral_Vs2 = 0;
    VoltageIntegrals(t_s, static_cast<int>(q), &integral_Vs, &double_integral_Vs2);
    const Block& block = blocks[q];
    for (int i = 0; i < block.size; ++i) {
      out[block.offset + i] += block.aab[i] * double_integral_Vs2;
    }
  }
}

void IpmcActuatorBank::Impl::StateFromEta(double t_s) {
  state = eta;
  if (!smooth) return;
  for (std::size_t q = 0; q < blocks.size(); ++q) {
    double integral_Vs = 0, double_integral_Vs2 = 0;
    VoltageIntegrals(t_s, static_cast<int>(q), &integral_Vs, &double_integral_Vs2);
    const Block& block = blocks[q];
    state.segment(block.offset, block.size) +=
        block.b * integral_Vs + block.ab * double_integral_Vs2;
  }
}

void IpmcActuatorBank::Impl::ApplyA(const double* in, const double* add, double* out) const {
  const double* value = a_value.data();
  for (int i = 0; i < states; ++i) {
    const double* row = value + a_start[i];
    const double* x = in + a_first[i];
    const int count = a_start[i + 1] - a_start[i];
    double sum = add ? add[i] : 0.0;
    for (int k = 0; k < count; ++k) sum += row[k] * x[k];
    out[i] = sum;
  }
}

// J = df/dx = A, constant: copied into the dense or band matrix.
int IpmcActuatorBank::Impl::Jacobian(realtype /*t*/, N_Vector /*x*/, N_Vector /*fx*/, SUNMatrix jac,
                                     void* user_data, N_Vector /*tmp1*/, N_Vector /*tmp2*/,
                                     N_Vector /*tmp3*/) {
  const auto* impl = static_cast<const Impl*>(user_data);
  const Eigen::MatrixXd& a = impl->jacobian;
  const int n = impl->states;
  if (SUNMatGetID(jac) == SUNMATRIX_DENSE) {
    std::memcpy(SUNDenseMatrix_Data(jac), a.data(),
                sizeof(double) * static_cast<std::size_t>(n) * n);
    return 0;
  }
  if (SUNMatZero(jac) != 0) return -1;
  for (int j = 0; j < n; ++j) {
    const int i_begin = std::max(0, j - impl->upper_bandwidth);
    const int i_end = std::min(n - 1, j + impl->lower_bandwidth);
    for (int i = i_begin; i <= i_end; ++i) SM_ELEMENT_B(jac, i, j) = a(i, j);
  }
  return 0;
}

// Keeps CVODE's last message for the exception instead of printing it.
void IpmcActuatorBank::Impl::CaptureMessage(int /*error_code*/, const char* /*module*/,
                                            const char* function, char* msg, void* user_data) {
  auto* impl = static_cast<Impl*>(user_data);
  impl->last_cvode_message = std::string(function) + ": " + msg;
}

void IpmcActuatorBank::Impl::Check(int flag, const char* call) const {
  if (flag >= 0) return;
  std::ostringstream out;
  out << "ipmc actuator: " << call << " failed at t = " << time_s << " s: " << FlagName(flag);
  if (!last_cvode_message.empty()) out << " (" << last_cvode_message << ")";
  throw std::runtime_error(out.str());
}

void IpmcActuatorBank::Impl::ThrowSolverFailure(int flag) {
  realtype t_reached = time_s;
  if (CVodeGetCurrentTime(cvode.get(), &t_reached) != CV_SUCCESS) {
    t_reached = time_s;
  }
  // Name the link whose states carry the largest weighted local error.
  VectorPtr errors(N_VClone(y_vector.get()));
  VectorPtr weights(N_VClone(y_vector.get()));
  int worst_link = -1;
  if (errors && weights && CVodeGetEstLocalErrors(cvode.get(), errors.get()) == CV_SUCCESS &&
      CVodeGetErrWeights(cvode.get(), weights.get()) == CV_SUCCESS) {
    const double* e = N_VGetArrayPointer(errors.get());
    const double* w = N_VGetArrayPointer(weights.get());
    double worst = -1;
    for (std::size_t q = 0; q < blocks.size(); ++q) {
      for (int i = blocks[q].offset; i < blocks[q].offset + blocks[q].size; ++i) {
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
  if (!last_cvode_message.empty()) out << ": " << last_cvode_message;
  throw std::runtime_error(out.str());
}

void IpmcActuatorBank::Impl::InitCvode() {
  SUNContext raw_context = nullptr;
  if (SUNContext_Create(nullptr, &raw_context) != 0 || raw_context == nullptr) {
    throw std::runtime_error("ipmc actuator: SUNContext_Create failed");
  }
  context.reset(raw_context);
  y_vector.reset(N_VMake_Serial(states, eta.data(), context.get()));
  if (!y_vector) throw std::runtime_error("ipmc actuator: N_VMake_Serial failed");
  serial_kernels::Install(y_vector.get());
  switch (options.linear_solver) {
    case CvodeLinearSolver::kBlockSchur:
      linear_solver.reset(NewSchurSolver());
      break;
    case CvodeLinearSolver::kDense:
      matrix.reset(SUNDenseMatrix(states, states, context.get()));
      if (!matrix) break;
      linear_solver.reset(SUNLinSol_Dense(y_vector.get(), matrix.get(), context.get()));
      break;
    case CvodeLinearSolver::kBand:
      matrix.reset(SUNBandMatrix(states, upper_bandwidth, lower_bandwidth, context.get()));
      if (!matrix) break;
      linear_solver.reset(SUNLinSol_Band(y_vector.get(), matrix.get(), context.get()));
      break;
  }
  if (!linear_solver) {
    throw std::runtime_error("ipmc actuator: linear solver creation failed");
  }
  cvode.reset(CVodeCreate(CV_BDF, context.get()));
  if (!cvode) throw std::runtime_error("ipmc actuator: CVodeCreate failed");
  void* mem = cvode.get();
  Check(CVodeSetErrHandlerFn(mem, CaptureMessage, this), "CVodeSetErrHandlerFn");
  Check(CVodeInit(mem, Rhs, time_s, y_vector.get()), "CVodeInit");
  Check(CVodeSetUserData(mem, this), "CVodeSetUserData");
  Check(CVodeSStolerances(mem, options.rel_tol, options.abs_tol_mm), "CVodeSStolerances");
  Check(CVodeSetMaxNumSteps(mem, options.max_steps), "CVodeSetMaxNumSteps");
  Check(CVodeSetLinearSolver(mem, linear_solver.get(), matrix.get()), "CVodeSetLinearSolver");
  if (matrix) Check(CVodeSetJacFn(mem, Jacobian), "CVodeSetJacFn");
  if (options.linear_solver == CvodeLinearSolver::kBlockSchur) {
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
double IpmcActuatorBank::Impl::InitialStep_s() {
  Derivative(time_s, eta.data(), derivative.data());
  ApplyA(derivative.data(), nullptr, second_derivative.data());
  double sum_squares = 0.0;
  for (int i = 0; i < states; ++i) {
    const double weighted =
        second_derivative[i] / (options.rel_tol * std::abs(eta[i]) + options.abs_tol_mm);
    sum_squares += weighted * weighted;
  }
  const double norm = std::sqrt(sum_squares / states);
  const double lower_s = 100.0 * std::numeric_limits<double>::epsilon() * std::abs(time_s);
  // (h^2 / 2) norm = 1/4
  if (!(initial_step_cap_s > 0.0)) return 0.0;  // A = 0: CVODE's own estimate
  const double step_s = norm > 0.0 ? std::sqrt(0.5 / norm) : initial_step_cap_s;
  return std::clamp(step_s, std::min(lower_s, initial_step_cap_s), initial_step_cap_s);
}

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

const char* ActuatorIntegrationName(ActuatorIntegration integration) {
  return integration == ActuatorIntegration::kExact ? "exact" : "cvode";
}

std::optional<ActuatorIntegration> ParseActuatorIntegration(const std::string& word) {
  if (word == "exact") return ActuatorIntegration::kExact;
  if (word == "cvode") return ActuatorIntegration::kCvode;
  return std::nullopt;
}

std::unique_ptr<IpmcActuatorBank> IpmcActuatorBank::Create(std::vector<IpmcLinkParams> links,
                                                           CvodeOptions options,
                                                           ActuatorIntegration integration) {
  std::vector<StateSpace> blocks;
  blocks.reserve(links.size());
  for (std::size_t q = 0; q < links.size(); ++q) {
    try {
      blocks.push_back(LinkStateSpace(links[q]));
    } catch (const std::invalid_argument& e) {
      std::ostringstream out;
      out << "ipmc actuator: link " << q + 1 << ": " << e.what();
      throw std::invalid_argument(out.str());
    }
  }
  return CreateFromStateSpace(std::move(blocks), options, integration);
}

std::unique_ptr<IpmcActuatorBank> IpmcActuatorBank::CreateFromStateSpace(
    std::vector<StateSpace> blocks, CvodeOptions options, ActuatorIntegration integration) {
  options.Validate();
  if (blocks.empty()) {
    throw std::invalid_argument("ipmc actuator: needs at least one link");
  }
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  for (std::size_t q = 0; q < blocks.size(); ++q) {
    const std::string what = "ipmc actuator: link " + std::to_string(q + 1);
    blocks[q].Validate(what.c_str());
    Block block;
    block.offset = impl->states;
    block.size = blocks[q].States();
    block.a = blocks[q].a;
    block.b = blocks[q].b.col(0);
    block.c = blocks[q].c.row(0);
    block.d = blocks[q].d(0, 0);
    impl->states += block.size;
    impl->blocks.push_back(std::move(block));
  }
  if (impl->states == 0) {
    throw std::invalid_argument("ipmc actuator: the links have no states");
  }
  const int n = impl->states;
  impl->jacobian = Eigen::MatrixXd::Zero(n, n);
  for (const Block& block : impl->blocks) {
    impl->jacobian.block(block.offset, block.offset, block.size, block.size) = block.a;
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (impl->jacobian(i, j) == 0) continue;
      impl->lower_bandwidth = std::max(impl->lower_bandwidth, i - j);
      impl->upper_bandwidth = std::max(impl->upper_bandwidth, j - i);
    }
  }
  impl->a_start.push_back(0);
  for (int i = 0; i < n; ++i) {
    int first = n, last = -1;
    for (int j = 0; j < n; ++j) {
      if (impl->jacobian(i, j) == 0) continue;
      first = std::min(first, j);
      last = j;
    }
    if (last < 0) first = last = 0;  // an empty row: one zero entry
    impl->a_first.push_back(first);
    for (int j = first; j <= last; ++j) impl->a_value.push_back(impl->jacobian(i, j));
    impl->a_start.push_back(static_cast<int>(impl->a_value.size()));
  }
  int largest_block = 0;
  for (Block& block : impl->blocks) {
    largest_block = std::max(largest_block, block.size);
    if (block.size == 0) continue;
    if (IsQuasiLowerTriangular(block.a)) {
      block.reversed = true;
      block.schur_t_rows = block.a.reverse().transpose();  // P a P, by rows
      continue;
    }
    const Eigen::RealSchur<Eigen::MatrixXd> schur(block.a);
    if (schur.info() != Eigen::Success) {
      throw std::invalid_argument("ipmc actuator: link " +
                                  std::to_string(&block - impl->blocks.data() + 1) +
                                  ": real Schur decomposition of a did not converge");
    }
    block.schur_q = schur.matrixU();
    block.schur_t_rows = schur.matrixT().transpose();
  }
  impl->schur_work = Eigen::VectorXd::Zero(largest_block);
  impl->derivative = Eigen::VectorXd::Zero(n);
  impl->second_derivative = Eigen::VectorXd::Zero(n);
  double fastest_rate = 0.0;
  for (Block& block : impl->blocks) {
    block.ab = block.a * block.b;
    block.aab = block.a * block.ab;
    if (block.size == 0) continue;
    const Eigen::VectorXcd eigenvalues =
        Eigen::EigenSolver<Eigen::MatrixXd>(block.a, false).eigenvalues();
    fastest_rate = std::max(fastest_rate, eigenvalues.cwiseAbs().maxCoeff());
  }
  // 0 if every a is zero (InitialStep_s then leaves the first step to CVODE).
  impl->initial_step_cap_s =
      fastest_rate > 0.0 && std::isfinite(fastest_rate) ? 1.0 / fastest_rate : 0.0;
  impl->forcing = Eigen::VectorXd::Zero(n);
  impl->state = Eigen::VectorXd::Zero(n);
  impl->eta = Eigen::VectorXd::Zero(n);
  impl->voltage_V.assign(impl->blocks.size(), 0.0);
  impl->segment_integral_Vs.assign(impl->blocks.size(), 0.0);
  impl->segment_double_integral_Vs2.assign(impl->blocks.size(), 0.0);
  impl->segment_voltage_V = impl->voltage_V;
  impl->pending_restart = Impl::PendingRestart::kPlain;
  if (integration == ActuatorIntegration::kExact) {
    std::vector<Eigen::MatrixXd> a;
    std::vector<Eigen::VectorXd> b;
    for (const Block& block : impl->blocks) {
      a.push_back(block.a);
      b.push_back(block.b);
    }
    impl->exact = std::make_unique<ZeroOrderHold>(std::move(a), std::move(b));
  } else {
    impl->InitCvode();
  }
  return std::unique_ptr<IpmcActuatorBank>(new IpmcActuatorBank(std::move(impl)));
}

IpmcActuatorBank::IpmcActuatorBank(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

IpmcActuatorBank::~IpmcActuatorBank() = default;

int IpmcActuatorBank::Links() const { return static_cast<int>(impl_->blocks.size()); }

int IpmcActuatorBank::States() const { return impl_->states; }

void IpmcActuatorBank::SetVoltages(const std::vector<double>& voltage_V) {
  if (voltage_V.size() != impl_->blocks.size()) {
    std::ostringstream out;
    out << "ipmc actuator: voltage_V needs " << impl_->blocks.size()
        << " values, one per link (got " << voltage_V.size() << ")";
    throw std::invalid_argument(out.str());
  }
  for (std::size_t q = 0; q < voltage_V.size(); ++q) {
    if (!std::isfinite(voltage_V[q])) {
      std::ostringstream out;
      out << "ipmc actuator: voltage_V of link " << q + 1 << " must be finite (got " << voltage_V[q]
          << ")";
      throw std::invalid_argument(out.str());
    }
  }
  for (std::size_t q = 0; q < voltage_V.size(); ++q) {
    if (voltage_V[q] == impl_->voltage_V[q]) continue;
    impl_->voltage_V[q] = voltage_V[q];
    const Block& block = impl_->blocks[q];
    impl_->forcing.segment(block.offset, block.size) = block.b * voltage_V[q];
    impl_->voltage_changed = true;
  }
}

const std::vector<double>& IpmcActuatorBank::Voltages_V() const { return impl_->voltage_V; }

void IpmcActuatorBank::Impl::RestartAt(bool smooth_form) {
  void* mem = cvode.get();
  long steps = 0;
  Check(CVodeGetNumSteps(mem, &steps), "CVodeGetNumSteps");
  steps_before_reinit += steps;
  smooth = smooth_form;
  base_s = segment_s = time_s;
  segment_integral_Vs.assign(blocks.size(), 0.0);
  segment_double_integral_Vs2.assign(blocks.size(), 0.0);
  segment_voltage_V = voltage_V;
  eta = state;  // P = Q = 0 at the restart
  // From x(time_s): no step taken with the old input beyond time_s is used.
  Check(CVodeReInit(mem, time_s, y_vector.get()), "CVodeReInit");
  Check(CVodeSetInitStep(mem, InitialStep_s()), "CVodeSetInitStep");
  Check(CVodeSetStopTime(mem, kNoStop_s), "CVodeSetStopTime");
  ++reinitialisations;
}

void IpmcActuatorBank::Impl::SetSmoothStop(double period_s) {
  double stop_s = segment_s + kRebase_s;
  if (period_s > 0.0) stop_s = std::min(stop_s, time_s + period_s);
  Check(CVodeSetStopTime(cvode.get(), stop_s), "CVodeSetStopTime");
}

void IpmcActuatorBank::Impl::OnVoltageChange() {
  realtype t_cvode = time_s;
  Check(CVodeGetCurrentTime(cvode.get(), &t_cvode), "CVodeGetCurrentTime");
  const double period_s = std::isfinite(last_change_s) ? time_s - last_change_s : 0.0;
  last_change_s = time_s;
  period_known = period_s > 0.0;
  const bool stopped_here = std::abs(t_cvode - time_s) <= Unresolvable_s(t_cvode, time_s);
  // Rebase at the first change in each kRebase_s window of absolute time,
  // the same instants in every bank that sees the same changes.
  const bool same_window = std::floor(time_s / kRebase_s) == std::floor(base_s / kRebase_s);
  if (smooth && stopped_here && same_window) {
    // Continue: P and Q stay continuous, the new voltages hold from here.
    for (std::size_t q = 0; q < blocks.size(); ++q) {
      double integral_Vs = 0, double_integral_Vs2 = 0;
      VoltageIntegrals(t_cvode, static_cast<int>(q), &integral_Vs,
                       &double_integral_Vs2);
      segment_integral_Vs[q] = integral_Vs;
      segment_double_integral_Vs2[q] = double_integral_Vs2;
    }
    segment_s = t_cvode;
    segment_voltage_V = voltage_V;
  } else {
    // CVODE went past the change (it did not know when it would come), or
    // this is the first change of a kRebase_s window: start again here, which is
    // gentler than a plain restart (eta has no kink at a restart).
    RestartAt(true);
  }
  SetSmoothStop(period_s);
}

void IpmcActuatorBank::Impl::Integrate(double t_s) {
  last_cvode_message.clear();
  realtype t_returned = time_s;
  for (;;) {
    const int flag = CVode(cvode.get(), t_s, y_vector.get(), &t_returned, CV_NORMAL);
    if (flag < 0) {
      // CVODE left the solution of its last successful step in eta:
      // continue from there (after a restart) if the caller retries.
      time_s = std::max(time_s, static_cast<double>(t_returned));
      StateFromEta(t_returned);
      pending_restart = PendingRestart::kPlain;
      ThrowSolverFailure(flag);
    }
    // At a stop CVODE drops the stop time. A stop where the voltages are
    // expected to change next is followed, unless they do change there
    // (OnVoltageChange sets a new stop), by one where a hold ends: there
    // the voltages have held for kRebase_s, P and Q would only grow, and
    // the plain form goes on.
    if (flag == CV_TSTOP_RETURN && smooth) {
      const double hold_end_s = segment_s + kRebase_s;
      if (t_returned >= hold_end_s - Unresolvable_s(t_returned, hold_end_s)) {
        time_s = t_returned;
        StateFromEta(t_returned);
        RestartAt(false);
      } else {
        Check(CVodeSetStopTime(cvode.get(), hold_end_s), "CVodeSetStopTime");
      }
    }
    if (flag != CV_TSTOP_RETURN || t_s - t_returned <= Unresolvable_s(t_s, t_returned)) break;
  }
  StateFromEta(t_returned);
  time_s = t_s;
}

void IpmcActuatorBank::AdvanceTo(double t_s) {
  Impl& impl = *impl_;
  if (!std::isfinite(t_s) || t_s < impl.time_s) {
    std::ostringstream out;
    out.precision(17);
    out << "ipmc actuator: AdvanceTo needs a finite t_s >= Time_s() = " << impl.time_s << " s (got "
        << t_s << ")";
    throw std::invalid_argument(out.str());
  }
  // CVODE cannot resolve an interval below a few ulps of t; such a step
  // leaves the state unchanged.
  if (t_s - impl.time_s <= Unresolvable_s(t_s, impl.time_s)) return;
  if (impl.exact) {
    impl.exact->Advance(t_s - impl.time_s, impl.voltage_V, &impl.state);
    impl.time_s = t_s;
    impl.voltage_changed = false;
    return;
  }
  if (impl.pending_restart != Impl::PendingRestart::kNone) {
    // The restart takes any new voltages; a change at this instant is the
    // first the bank knows of.
    impl.last_change_s =
        impl.voltage_changed ? impl.time_s : std::numeric_limits<double>::quiet_NaN();
    // A state at rest restarts in the plain form whichever restart asked
    // for it, so that a bank reset (or new) and then saved or restored
    // steps as a new one does.
    const bool smooth_form =
        impl.pending_restart == Impl::PendingRestart::kSmooth && (impl.state.array() != 0.0).any();
    impl.RestartAt(smooth_form);
    impl.period_known = false;
  } else if (impl.voltage_changed) {
    impl.OnVoltageChange();
  }
  impl.pending_restart = Impl::PendingRestart::kNone;
  impl.voltage_changed = false;
  if (impl.smooth && !impl.period_known) {
    impl.Check(CVodeSetStopTime(impl.cvode.get(), std::min(t_s, impl.segment_s + kRebase_s)),
               "CVodeSetStopTime");
  }
  impl.Integrate(t_s);
}

double IpmcActuatorBank::FreeTipDeflection_mm(int link) const {
  const Block& block = impl_->blocks.at(link);
  return block.c.dot(impl_->state.segment(block.offset, block.size)) +
         block.d * impl_->voltage_V[link];
}

std::vector<double> IpmcActuatorBank::FreeTipDeflection_mm() const {
  std::vector<double> out(impl_->blocks.size());
  for (std::size_t q = 0; q < out.size(); ++q) out[q] = FreeTipDeflection_mm(static_cast<int>(q));
  return out;
}

double IpmcActuatorBank::Time_s() const { return impl_->time_s; }

void IpmcActuatorBank::Reset(double t0_s) {
  if (!std::isfinite(t0_s)) {
    std::ostringstream out;
    out << "ipmc actuator: Reset needs a finite t0_s (got " << t0_s << ")";
    throw std::invalid_argument(out.str());
  }
  impl_->state.setZero();
  impl_->time_s = t0_s;
  impl_->pending_restart = Impl::PendingRestart::kPlain;
  impl_->voltage_changed = false;  // the restart takes the voltages as they are
}

void IpmcActuatorBank::SetState(double t_s, const Eigen::VectorXd& state) {
  if (!std::isfinite(t_s)) {
    std::ostringstream out;
    out << "ipmc actuator: SetState needs a finite t_s (got " << t_s << ")";
    throw std::invalid_argument(out.str());
  }
  if (state.size() != impl_->states) {
    std::ostringstream out;
    out << "ipmc actuator: state needs " << impl_->states << " values (got " << state.size() << ")";
    throw std::invalid_argument(out.str());
  }
  if (!state.allFinite()) {
    throw std::invalid_argument("ipmc actuator: state values must be finite");
  }
  impl_->state = state;
  impl_->time_s = t_s;
  impl_->pending_restart = Impl::PendingRestart::kSmooth;
  impl_->voltage_changed = false;  // the restart takes the voltages as they are
}

void IpmcActuatorBank::Restart() {
  impl_->pending_restart = Impl::PendingRestart::kSmooth;
  impl_->voltage_changed = false;
}

const Eigen::VectorXd& IpmcActuatorBank::State() const { return impl_->state; }

long IpmcActuatorBank::InternalSteps() const {
  if (impl_->exact) return impl_->exact->Advances();
  long steps = 0;
  impl_->Check(CVodeGetNumSteps(impl_->cvode.get(), &steps), "CVodeGetNumSteps");
  return impl_->steps_before_reinit + steps;
}

long IpmcActuatorBank::Reinitialisations() const { return impl_->reinitialisations; }

}  // namespace ipmc
