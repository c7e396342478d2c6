#include "plugin/actuators/ipmc_actuator_bank.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include <Eigen/Eigenvalues>

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_band.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_band.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "plugin/actuators/serial_kernels.h"

namespace ipmc {
namespace {

// RAII owners of the SUNDIALS objects. Impl declares them in creation
// order, so C++ destroys them in reverse: CVODE memory, linear solver,
// matrix, vector, context.
struct ContextFree {
  void operator()(SUNContext context) const { SUNContext_Free(&context); }
};
struct VectorFree {
  void operator()(N_Vector v) const { N_VDestroy(v); }
};
struct MatrixFree {
  void operator()(SUNMatrix m) const { SUNMatDestroy(m); }
};
struct LinearSolverFree {
  void operator()(SUNLinearSolver s) const { SUNLinSolFree(s); }
};
struct CvodeFree {
  void operator()(void* mem) const { CVodeFree(&mem); }
};
using ContextPtr = std::unique_ptr<std::remove_pointer_t<SUNContext>, ContextFree>;
using VectorPtr = std::unique_ptr<std::remove_pointer_t<N_Vector>, VectorFree>;
using MatrixPtr = std::unique_ptr<std::remove_pointer_t<SUNMatrix>, MatrixFree>;
using LinearSolverPtr =
    std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, LinearSolverFree>;
using CvodePtr = std::unique_ptr<void, CvodeFree>;

struct Block {
  int offset = 0;  // first state in x
  int size = 0;
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
  Eigen::RowVectorXd c;
  double d = 0;
  // Real Schur form a = schur_q * schur_t * schur_q^T (kBlockSchur only).
  Eigen::MatrixXd schur_q;
  Eigen::MatrixXd schur_t;
};

// Solves (I - gamma T) w = z in place for quasi-upper-triangular T (1x1 and
// 2x2 diagonal blocks) by back substitution. Returns false if a pivot
// vanishes (an unstable block with 1 - gamma lambda = 0).
bool SolveShiftedQuasiTriangular(const Eigen::MatrixXd& t, double gamma,
                                 Eigen::Ref<Eigen::VectorXd> z) {
  const Eigen::Index n = t.rows();
  constexpr double kTiny = 1e-300;
  Eigen::Index i = n - 1;
  while (i >= 0) {
    const bool pair = i > 0 && t(i, i - 1) != 0.0;
    const Eigen::Index top = pair ? i - 1 : i;
    const Eigen::Index tail = n - 1 - i;
    for (Eigen::Index k = top; k <= i; ++k) {
      if (tail > 0) {
        z(k) += gamma * t.row(k).tail(tail).dot(z.tail(tail));
      }
    }
    if (!pair) {
      const double pivot = 1.0 - gamma * t(i, i);
      if (std::abs(pivot) < kTiny) return false;
      z(i) /= pivot;
    } else {
      // [1 - g t00, -g t01; -g t10, 1 - g t11] [w0; w1] = [z0; z1]
      const double m00 = 1.0 - gamma * t(top, top);
      const double m01 = -gamma * t(top, i);
      const double m10 = -gamma * t(i, top);
      const double m11 = 1.0 - gamma * t(i, i);
      const double det = m00 * m11 - m01 * m10;
      if (std::abs(det) < kTiny) return false;
      const double z0 = z(top);
      const double z1 = z(i);
      z(top) = (m11 * z0 - m01 * z1) / det;
      z(i) = (m00 * z1 - m10 * z0) / det;
    }
    i = top - 1;
  }
  return true;
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
  Eigen::VectorXd forcing;   // B u for the held u
  Eigen::VectorXd state;     // x at time_s; y_vector wraps its storage
  std::vector<double> voltage_V;
  double time_s = 0;
  bool reinit_pending = false;
  long steps_before_reinit = 0;
  long reinitialisations = 0;
  int lower_bandwidth = 0;
  int upper_bandwidth = 0;
  CvodeOptions options;
  std::string last_cvode_message;
  Eigen::VectorXd schur_work;  // Q^T r of one block

  ContextPtr context;
  VectorPtr y_vector;
  MatrixPtr matrix;
  LinearSolverPtr linear_solver;
  CvodePtr cvode;

  void Check(int flag, const char* call) const;
  [[noreturn]] void ThrowSolverFailure(int flag);
  void InitCvode();

  // CVODE callbacks; user_data is the Impl.
  static int Rhs(realtype t, N_Vector x, N_Vector xdot, void* user_data);
  static int Jacobian(realtype t, N_Vector x, N_Vector fx, SUNMatrix jac,
                      void* user_data, N_Vector tmp1, N_Vector tmp2,
                      N_Vector tmp3);
  static void CaptureMessage(int error_code, const char* module,
                             const char* function, char* msg,
                             void* user_data);
  // Matrix-embedded linear solver (kBlockSchur); content is the Impl.
  static SUNLinearSolver_Type SchurType(SUNLinearSolver solver);
  static int SchurSolve(SUNLinearSolver solver, SUNMatrix unused, N_Vector x,
                        N_Vector r, realtype tol);
  static int SchurFree(SUNLinearSolver solver);
  SUNLinearSolver NewSchurSolver();
};

SUNLinearSolver_Type IpmcActuatorBank::Impl::SchurType(
    SUNLinearSolver /*solver*/) {
  return SUNLINEARSOLVER_MATRIX_EMBEDDED;
}

// x = (I - gamma A)^-1 r block by block, x_q = Q (I - gamma T)^-1 Q^T r_q,
// with CVODE's current gamma.
int IpmcActuatorBank::Impl::SchurSolve(SUNLinearSolver solver,
                                       SUNMatrix /*unused*/, N_Vector x,
                                       N_Vector r, realtype /*tol*/) {
  auto* impl = static_cast<Impl*>(solver->content);
  realtype gamma = 0;
  if (CVodeGetCurrentGamma(impl->cvode.get(), &gamma) != CV_SUCCESS) {
    return SUNLS_MEM_NULL;
  }
  const Eigen::Map<const Eigen::VectorXd> r_map(N_VGetArrayPointer(r),
                                                impl->states);
  Eigen::Map<Eigen::VectorXd> x_map(N_VGetArrayPointer(x), impl->states);
  for (const Block& block : impl->blocks) {
    auto work = impl->schur_work.head(block.size);
    work.noalias() =
        block.schur_q.transpose() * r_map.segment(block.offset, block.size);
    if (!SolveShiftedQuasiTriangular(block.schur_t, gamma, work)) {
      return SUNLS_LUFACT_FAIL;  // recoverable: CVODE retries a smaller step
    }
    x_map.segment(block.offset, block.size).noalias() = block.schur_q * work;
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

// dx/dt = A x + B u, evaluated block by block.
int IpmcActuatorBank::Impl::Rhs(realtype /*t*/, N_Vector x, N_Vector xdot,
                                void* user_data) {
  const auto* impl = static_cast<const Impl*>(user_data);
  const Eigen::Map<const Eigen::VectorXd> x_map(N_VGetArrayPointer(x),
                                                impl->states);
  Eigen::Map<Eigen::VectorXd> xdot_map(N_VGetArrayPointer(xdot),
                                       impl->states);
  for (const Block& block : impl->blocks) {
    xdot_map.segment(block.offset, block.size).noalias() =
        block.a * x_map.segment(block.offset, block.size);
  }
  xdot_map += impl->forcing;
  return 0;
}

// J = df/dx = A, constant: copied into the dense or band matrix.
int IpmcActuatorBank::Impl::Jacobian(realtype /*t*/, N_Vector /*x*/,
                                     N_Vector /*fx*/, SUNMatrix jac,
                                     void* user_data, N_Vector /*tmp1*/,
                                     N_Vector /*tmp2*/, N_Vector /*tmp3*/) {
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
void IpmcActuatorBank::Impl::CaptureMessage(int /*error_code*/,
                                            const char* /*module*/,
                                            const char* function, char* msg,
                                            void* user_data) {
  auto* impl = static_cast<Impl*>(user_data);
  impl->last_cvode_message = std::string(function) + ": " + msg;
}

void IpmcActuatorBank::Impl::Check(int flag, const char* call) const {
  if (flag >= 0) return;
  std::ostringstream out;
  out << "ipmc actuator: " << call << " failed at t = " << time_s
      << " s: " << FlagName(flag);
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
  if (errors && weights &&
      CVodeGetEstLocalErrors(cvode.get(), errors.get()) == CV_SUCCESS &&
      CVodeGetErrWeights(cvode.get(), weights.get()) == CV_SUCCESS) {
    const double* e = N_VGetArrayPointer(errors.get());
    const double* w = N_VGetArrayPointer(weights.get());
    double worst = -1;
    for (std::size_t q = 0; q < blocks.size(); ++q) {
      for (int i = blocks[q].offset; i < blocks[q].offset + blocks[q].size;
           ++i) {
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
    out << "link " << worst_link << " of " << blocks.size()
        << " has the largest local error";
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
  y_vector.reset(N_VMake_Serial(states, state.data(), context.get()));
  if (!y_vector) throw std::runtime_error("ipmc actuator: N_VMake_Serial failed");
  serial_kernels::Install(y_vector.get());
  switch (options.linear_solver) {
    case CvodeLinearSolver::kBlockSchur:
      linear_solver.reset(NewSchurSolver());
      break;
    case CvodeLinearSolver::kDense:
      matrix.reset(SUNDenseMatrix(states, states, context.get()));
      if (!matrix) break;
      linear_solver.reset(
          SUNLinSol_Dense(y_vector.get(), matrix.get(), context.get()));
      break;
    case CvodeLinearSolver::kBand:
      matrix.reset(SUNBandMatrix(states, upper_bandwidth, lower_bandwidth,
                                 context.get()));
      if (!matrix) break;
      linear_solver.reset(
          SUNLinSol_Band(y_vector.get(), matrix.get(), context.get()));
      break;
  }
  if (!linear_solver) {
    throw std::runtime_error("ipmc actuator: linear solver creation failed");
  }
  cvode.reset(CVodeCreate(CV_BDF, context.get()));
  if (!cvode) throw std::runtime_error("ipmc actuator: CVodeCreate failed");
  void* mem = cvode.get();
  Check(CVodeSetErrHandlerFn(mem, CaptureMessage, this),
        "CVodeSetErrHandlerFn");
  Check(CVodeInit(mem, Rhs, time_s, y_vector.get()), "CVodeInit");
  Check(CVodeSetUserData(mem, this), "CVodeSetUserData");
  Check(CVodeSStolerances(mem, options.rel_tol, options.abs_tol_mm),
        "CVodeSStolerances");
  Check(CVodeSetMaxNumSteps(mem, options.max_steps), "CVodeSetMaxNumSteps");
  Check(CVodeSetLinearSolver(mem, linear_solver.get(), matrix.get()),
        "CVodeSetLinearSolver");
  if (matrix) Check(CVodeSetJacFn(mem, Jacobian), "CVodeSetJacFn");
}

void CvodeOptions::Validate() const {
  if (linear_solver != CvodeLinearSolver::kBlockSchur &&
      linear_solver != CvodeLinearSolver::kDense &&
      linear_solver != CvodeLinearSolver::kBand) {
    throw std::invalid_argument(
        "ipmc actuator: linear_solver must be kBlockSchur, kDense or kBand");
  }
  if (!(rel_tol >= 1e-14 && rel_tol <= 1e-2)) {
    std::ostringstream out;
    out << "ipmc actuator: rel_tol must be in [1e-14, 1e-2] (got " << rel_tol
        << ")";
    throw std::invalid_argument(out.str());
  }
  if (!std::isfinite(abs_tol_mm) || abs_tol_mm <= 0) {
    std::ostringstream out;
    out << "ipmc actuator: abs_tol_mm must be finite and > 0 (got "
        << abs_tol_mm << ")";
    throw std::invalid_argument(out.str());
  }
  if (max_steps < 1) {
    std::ostringstream out;
    out << "ipmc actuator: max_steps must be >= 1 (got " << max_steps << ")";
    throw std::invalid_argument(out.str());
  }
}

std::unique_ptr<IpmcActuatorBank> IpmcActuatorBank::Create(
    std::vector<IpmcLinkParams> links, CvodeOptions options) {
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
  return CreateFromStateSpace(std::move(blocks), options);
}

std::unique_ptr<IpmcActuatorBank> IpmcActuatorBank::CreateFromStateSpace(
    std::vector<StateSpace> blocks, CvodeOptions options) {
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
    impl->jacobian.block(block.offset, block.offset, block.size, block.size) =
        block.a;
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (impl->jacobian(i, j) == 0) continue;
      impl->lower_bandwidth = std::max(impl->lower_bandwidth, i - j);
      impl->upper_bandwidth = std::max(impl->upper_bandwidth, j - i);
    }
  }
  int largest_block = 0;
  for (Block& block : impl->blocks) {
    largest_block = std::max(largest_block, block.size);
    if (block.size == 0) continue;
    const Eigen::RealSchur<Eigen::MatrixXd> schur(block.a);
    if (schur.info() != Eigen::Success) {
      throw std::invalid_argument(
          "ipmc actuator: link " +
          std::to_string(&block - impl->blocks.data() + 1) +
          ": real Schur decomposition of a did not converge");
    }
    block.schur_q = schur.matrixU();
    block.schur_t = schur.matrixT();
  }
  impl->schur_work = Eigen::VectorXd::Zero(largest_block);
  impl->forcing = Eigen::VectorXd::Zero(n);
  impl->state = Eigen::VectorXd::Zero(n);
  impl->voltage_V.assign(impl->blocks.size(), 0.0);
  impl->InitCvode();
  return std::unique_ptr<IpmcActuatorBank>(
      new IpmcActuatorBank(std::move(impl)));
}

IpmcActuatorBank::IpmcActuatorBank(std::unique_ptr<Impl> impl)
    : impl_(std::move(impl)) {}

IpmcActuatorBank::~IpmcActuatorBank() = default;

int IpmcActuatorBank::Links() const {
  return static_cast<int>(impl_->blocks.size());
}

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
      out << "ipmc actuator: voltage_V of link " << q + 1
          << " must be finite (got " << voltage_V[q] << ")";
      throw std::invalid_argument(out.str());
    }
  }
  for (std::size_t q = 0; q < voltage_V.size(); ++q) {
    if (voltage_V[q] == impl_->voltage_V[q]) continue;
    impl_->voltage_V[q] = voltage_V[q];
    const Block& block = impl_->blocks[q];
    impl_->forcing.segment(block.offset, block.size) =
        block.b * voltage_V[q];
    impl_->reinit_pending = true;
  }
}

const std::vector<double>& IpmcActuatorBank::Voltages_V() const {
  return impl_->voltage_V;
}

void IpmcActuatorBank::AdvanceTo(double t_s) {
  Impl& impl = *impl_;
  if (!std::isfinite(t_s) || t_s < impl.time_s) {
    std::ostringstream out;
    out.precision(17);
    out << "ipmc actuator: AdvanceTo needs a finite t_s >= Time_s() = "
        << impl.time_s << " s (got " << t_s << ")";
    throw std::invalid_argument(out.str());
  }
  // CVODE cannot resolve an interval below a few ulps of t; such a step
  // leaves the state unchanged.
  const double resolvable =
      8.0 * std::numeric_limits<double>::epsilon() *
      std::max({1.0, std::abs(t_s), std::abs(impl.time_s)});
  if (t_s - impl.time_s <= resolvable) return;
  void* mem = impl.cvode.get();
  if (impl.reinit_pending) {
    long steps = 0;
    impl.Check(CVodeGetNumSteps(mem, &steps), "CVodeGetNumSteps");
    impl.steps_before_reinit += steps;
    // state holds x(time_s): restart there so no step taken with the old
    // input beyond time_s is used.
    impl.Check(CVodeReInit(mem, impl.time_s, impl.y_vector.get()),
               "CVodeReInit");
    ++impl.reinitialisations;
    impl.reinit_pending = false;
  }
  impl.last_cvode_message.clear();
  realtype t_returned = impl.time_s;
  const int flag =
      CVode(mem, t_s, impl.y_vector.get(), &t_returned, CV_NORMAL);
  if (flag < 0) {
    // CVODE left the solution of its last successful step in the state:
    // continue from there (after a restart) if the caller retries.
    impl.time_s = std::max(impl.time_s, static_cast<double>(t_returned));
    impl.reinit_pending = true;
    impl.ThrowSolverFailure(flag);
  }
  impl.time_s = t_s;
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
  impl_->reinit_pending = true;
}

void IpmcActuatorBank::SetState(double t_s, const Eigen::VectorXd& state) {
  if (!std::isfinite(t_s)) {
    std::ostringstream out;
    out << "ipmc actuator: SetState needs a finite t_s (got " << t_s << ")";
    throw std::invalid_argument(out.str());
  }
  if (state.size() != impl_->states) {
    std::ostringstream out;
    out << "ipmc actuator: state needs " << impl_->states << " values (got "
        << state.size() << ")";
    throw std::invalid_argument(out.str());
  }
  if (!state.allFinite()) {
    throw std::invalid_argument("ipmc actuator: state values must be finite");
  }
  impl_->state = state;  // keeps the storage y_vector wraps
  impl_->time_s = t_s;
  impl_->reinit_pending = true;
}

void IpmcActuatorBank::Restart() { impl_->reinit_pending = true; }

const Eigen::VectorXd& IpmcActuatorBank::State() const {
  return impl_->state;
}

long IpmcActuatorBank::InternalSteps() const {
  long steps = 0;
  impl_->Check(CVodeGetNumSteps(impl_->cvode.get(), &steps),
               "CVodeGetNumSteps");
  return impl_->steps_before_reinit + steps;
}

long IpmcActuatorBank::Reinitialisations() const {
  return impl_->reinitialisations;
}

}  // namespace ipmc
