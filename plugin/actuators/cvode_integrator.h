// The stacked linear system (plugin/actuators/stacked_linear_system.h),
// dx/dt = A x + B u with u held between changes, integrated by SUNDIALS
// 6.4 CVODE (A. C. Hindmarsh et al., "SUNDIALS: Suite of nonlinear and
// differential/algebraic equation solvers", ACM TOMS 31(3), 2005):
// variable-order BDF with Newton iteration on
// (I - gamma J) dx = r, J = A (constant, analytic), solved by one of
//  - kBlockSchur (default): a matrix-embedded linear solver that uses the
//    block-diagonal structure of A. Each link block is put once in real
//    Schur form A_q = Q_q T_q Q_q^T (Q_q orthogonal, T_q quasi-upper-
//    triangular), and every solve is x_q = Q_q (I - gamma T_q)^-1 Q_q^T r_q
//    by back substitution with the current gamma: exact Newton, no
//    factorisation, cost O(sum n_q^2) per solve.
//  - kDense: SUNDenseMatrix + SUNLinSol_Dense, Jacobian callback copying A.
//  - kBand: SUNBandMatrix + SUNLinSol_Band with the bandwidths of A,
//    Jacobian callback copying A.
// All three give the same solution to within the tolerances. kBlockSchur
// never factorises; the dense and band solvers refactor the whole stacked
// matrix whenever gamma changes enough, which after every voltage change
// makes them 3-7x slower.
// Tolerances are scalar, kRelTol / kAbsTol: the realisations keep every
// state at the scale of the volts or millimetres it carries, so one
// absolute tolerance serves all states.
//
// Stepping: CVODE takes its own internal steps and Advance returns the
// interpolated state at the requested time (CV_NORMAL), so calling
// Advance once per MuJoCo step costs little more than an interpolation
// while the input is unchanged; an input that does not change costs
// nothing. A voltage change is a kink in x (dx/dt jumps by B du), which
// BDF cannot step across: CVODE has to restart there (CVodeReInit), at
// order 1 with small steps, about 5-8 internal steps per 1 ms interval
// for the paper's links at rel_tol 1e-6. So CVODE integrates
//
//   eta = x - B P(t) - A B Q(t),   P' = u, Q' = P (P, Q = 0 at a restart),
//   d eta/dt = A eta + A^2 B Q(t)                    ("smooth form"),
//
// an exact change of variables: x = eta + B P + A B Q. Q is continuous
// with its derivative and only Q'' = u jumps, so eta is three times
// continuously differentiable across a voltage change and CVODE steps on
// at its own order and step size, without a restart. This needs CVODE to
// be exactly at the change (a step taken past it used the old input):
// after two changes the integrator expects the next one a period later and
// stops CVODE there (CVodeSetStopTime); after a restart from a set or
// saved state (SetState, Restart), which knows no period, it stops CVODE
// at every Advance until it has seen two changes. A change anywhere else
// restarts CVODE, and so does the first change in each 0.1 s window of
// absolute time (kRebase_s), which keeps P and Q, and so the cancellation
// in x = eta + ..., bounded; the windows being absolute, two integrators
// that differ only by a save restart at the same instants after it and
// keep together. Voltages held for 0.1 s go back to the plain form eta = x,
// d eta/dt = A x + B u, which costs nothing while they hold. Measured on
// the paper's three G1 links with the voltages changed every 1 ms and the
// bank advanced every 0.5 ms (ipmc_actuator_bank_test), at rel_tol 1e-8:
// 4.7 internal steps per change and a relative error of 2e-8 against
// the exact solution, where restarting at every change took 16.5 steps
// for 2e-7.
// Every restart starts with the step InitialStep_s gives (no iterative
// estimate), and since the Schur solve is exact the Newton iteration of
// this linear ODE takes one correction (CVodeSetNonlinConvCoef).
//
// The vectors CVODE uses run on serial N_Vector kernels compiled with the
// project (plugin/actuators/serial_kernels.h).
#pragma once

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <cvode/cvode.h>

#include "plugin/actuators/cvode_options.h"
#include "plugin/actuators/linear_system_integrator.h"
#include "plugin/actuators/stacked_linear_system.h"
#include "plugin/actuators/sundials_handles.h"

namespace ipmc {

class CvodeIntegrator : public LinearSystemIntegrator {
 public:
  // `system` must outlive the integrator; `options` are valid
  // (CvodeOptions::Validate). Throws std::invalid_argument naming the link
  // if a block's real Schur decomposition does not converge, and
  // std::runtime_error if SUNDIALS cannot create its objects.
  CvodeIntegrator(const StackedLinearSystem& system, const CvodeOptions& options);
  ~CvodeIntegrator() override;
  CvodeIntegrator(const CvodeIntegrator&) = delete;
  CvodeIntegrator& operator=(const CvodeIntegrator&) = delete;

  void HeldInputChanged(const std::vector<double>& held_input_V) override;
  // Throws std::runtime_error naming the time, the link with the largest
  // local error estimate and the CVODE flag if CVODE fails.
  void Advance(double t1_s, const std::vector<double>& held_input_V) override;

  long InternalSteps() const override;
  long Reinitialisations() const override { return reinitialisations_; }

 private:
  // What one link block needs beyond the model: the smooth form's input
  // terms a b and a^2 b, and its real Schur form a = schur_q * T * schur_q^T
  // for the kBlockSchur solve. schur_t_rows holds T by rows (the transpose,
  // column-major), the order in which the back substitution reads it. A
  // block whose a is already quasi-lower-triangular (the Oustaloup cascades
  // of G1: each section driven by the ones before it) needs no rotation:
  // T = P a P with P the reversal of the states, and schur_q stays empty.
  struct BlockFactors {
    Eigen::VectorXd ab, aab;
    Eigen::MatrixXd schur_q;
    Eigen::MatrixXd schur_t_rows;
    bool reversed = false;  // Q = P instead of schur_q
  };
  // A restart due at the next Advance, and in which form: the plain one
  // from rest, the smooth one from a state set or saved.
  enum class PendingRestart { kNone, kPlain, kSmooth };

  void StartAfresh(Start start) override;
  void FactorBlocks();
  void CreateCvode();
  void CreateLinearSolver();
  void Check(int flag, const char* call) const;
  [[noreturn]] void ThrowSolverFailure(int flag);
  // forcing_ = B u for the held u, link by link where it changed.
  void UpdateForcing(const std::vector<double>& held_input_V);
  // P_q(t) and Q_q(t) of link q in the current segment: the integral of
  // its voltage [V s] and the integral of that [V s^2].
  void VoltageIntegrals(double t_s, int link, double* integral_Vs,
                        double* double_integral_Vs2) const;
  // out = d eta / dt at t for eta = in, in the current form.
  void Derivative(double t_s, const double* in, double* out) const;
  // x at t from eta at t.
  void StateFromEta(double t_s);
  // CVODE's first step from a restart at time_s_.
  double InitialStep_s();
  // Restarts CVODE at time_s_ from state_, in the smooth or the plain form.
  void RestartAt(bool smooth_form);
  // The stop time of the smooth form: the next change if it keeps the
  // period, or where a hold would end, whichever comes first.
  void SetSmoothStop(double period_s);
  // The voltages changed at time_s_: continue smoothly or restart.
  void OnVoltageChange();
  // Integrates to t_s and sets time_s_ and state_.
  void Integrate(double t_s);

  // CVODE callbacks; user_data is the integrator.
  static int Rhs(realtype t, N_Vector x, N_Vector xdot, void* user_data);
  static int Jacobian(realtype t, N_Vector x, N_Vector fx, SUNMatrix jac, void* user_data,
                      N_Vector tmp1, N_Vector tmp2, N_Vector tmp3);
  static void CaptureMessage(int error_code, const char* module, const char* function, char* msg,
                             void* user_data);
  // Matrix-embedded linear solver (kBlockSchur); content is the integrator.
  static SUNLinearSolver_Type SchurType(SUNLinearSolver solver);
  static int SchurSolve(SUNLinearSolver solver, SUNMatrix unused, N_Vector x, N_Vector r,
                        realtype tol);
  static int SchurFree(SUNLinearSolver solver);
  SUNLinearSolver NewSchurSolver();

  // Fixed at creation.
  const StackedLinearSystem& system_;
  const CvodeOptions options_;
  std::vector<BlockFactors> factors_;
  double initial_step_cap_s_ = 0;  // 1 / the fastest eigenvalue of A

  // The held input and B u for it (the plain form's forcing).
  std::vector<double> held_input_V_;
  Eigen::VectorXd forcing_;
  // What CVODE integrates (header, "Stepping"); y_vector_ wraps its storage.
  // The plain form: eta = x. The smooth form: eta = x - B P(t) - A B Q(t)
  // with P and Q the first and second integrals of u since the last
  // restart, base_s_; the current voltages hold from segment_s_, where
  // link q's voltage integrals were segment_integral_Vs_[q] and
  // segment_double_integral_Vs2_[q].
  Eigen::VectorXd eta_;
  bool smooth_ = false;
  double base_s_ = 0, segment_s_ = 0;
  std::vector<double> segment_integral_Vs_, segment_double_integral_Vs2_, segment_voltage_V_;
  PendingRestart pending_restart_ = PendingRestart::kPlain;
  bool input_changed_ = false;  // the held input changed at time_s_
  // The time of the last voltage change since the last restart (NaN: none).
  double last_change_s_ = std::numeric_limits<double>::quiet_NaN();
  // The smooth form expects the next change a period after the last; with
  // no period seen since its restart it stops CVODE at every Advance, so
  // that CVODE is at the change, wherever it comes.
  bool period_known_ = false;
  long steps_before_reinit_ = 0;
  long reinitialisations_ = 0;
  std::string last_cvode_message_;

  // Per-step workspace.
  Eigen::VectorXd schur_work_;                      // Q^T r of one block
  Eigen::VectorXd derivative_, second_derivative_;  // eta' and eta'' at a restart

  // Declared in creation order, destroyed in reverse.
  sundials_handles::ContextPtr context_;
  sundials_handles::VectorPtr y_vector_;
  sundials_handles::MatrixPtr matrix_;
  sundials_handles::LinearSolverPtr linear_solver_;
  sundials_handles::CvodePtr cvode_;
};

}  // namespace ipmc
