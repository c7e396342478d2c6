// The IPMC actuators of a flagellum as one linear ODE integrated by CVODE.
//
// Each link q is a SISO state-space block (plugin/actuators/ipmc_link_model.h), voltage
// u_q [V] -> free tip deflection y_q [mm]. The blocks are stacked into the
// augmented Oustaloup state x = [x_1; ...; x_L] with block-diagonal A:
//
//   dx/dt = A x + B u,   y_q = c_q x_q + d_q u_q,
//
// u held constant between SetVoltages calls that change it. The ODE is
// integrated by SUNDIALS 6.4 CVODE (A. C. Hindmarsh et al., "SUNDIALS: Suite
// of nonlinear and differential/algebraic equation solvers", ACM TOMS 31(3),
// 2005): variable-order BDF with Newton iteration on
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
// Stepping: CVODE takes its own internal steps and AdvanceTo returns the
// interpolated state at the requested time (CV_NORMAL), so calling
// AdvanceTo once per MuJoCo step costs little more than an interpolation
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
// after two changes the bank expects the next one a period later and
// stops CVODE there (CVodeSetStopTime); after a restart from a set or
// saved state (SetState, Restart), which knows no period, it stops CVODE
// at every AdvanceTo until it has seen two changes. A change anywhere else
// restarts CVODE, and so does the first change in each 0.1 s window of
// absolute time (kRebase_s), which keeps P and Q, and so the cancellation
// in x = eta + ..., bounded; the windows being absolute, two banks that
// differ only by a save restart at the same instants after it and keep
// together. Voltages held for 0.1 s go back to the plain form eta = x,
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
// Exact integration (ActuatorIntegration::kExact): the same ODE advanced
// over each AdvanceTo interval by its zero-order-hold matrices
// (plugin/actuators/zero_order_hold.h), exact to rounding since the
// voltages are held between SetVoltages calls; CVODE is not created.
//
// The bank replaces the serial N_Vector kernels of the vectors CVODE uses
// with equivalent loops compiled with the project (plugin/actuators/serial_kernels.h).
#ifndef IPMC_SWIM_PLUGIN_IPMC_ACTUATOR_BANK_H_
#define IPMC_SWIM_PLUGIN_IPMC_ACTUATOR_BANK_H_

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "controllers/linear/state_space.h"
#include "plugin/actuators/ipmc_link_model.h"

namespace ipmc {

// Default CVODE tolerances: relative, and absolute per state (mm or V).
constexpr double kRelTol = 1e-8;
constexpr double kAbsTol = 1e-10;
// Default cap on internal steps per AdvanceTo call.
constexpr int kMaxStepsPerAdvance = 100000;

enum class CvodeLinearSolver { kBlockSchur, kDense, kBand };

// How a bank advances its state: by CVODE (above), or exactly, the
// voltages held constant over each AdvanceTo interval, by the interval's
// matrix exponential (plugin/actuators/zero_order_hold.h; the options'
// tolerances then play no part).
enum class ActuatorIntegration { kCvode, kExact };

// "cvode" / "exact"; ParseActuatorIntegration returns nullopt for any
// other word.
const char* ActuatorIntegrationName(ActuatorIntegration integration);
std::optional<ActuatorIntegration> ParseActuatorIntegration(const std::string& word);

struct CvodeOptions {
  CvodeLinearSolver linear_solver = CvodeLinearSolver::kBlockSchur;
  double rel_tol = kRelTol;      // in [1e-14, 1e-2]
  double abs_tol_mm = kAbsTol;   // > 0, finite; applied to every state
  int max_steps = kMaxStepsPerAdvance;  // >= 1, per AdvanceTo call

  // Throws std::invalid_argument naming the field and its allowed range.
  void Validate() const;
};

class IpmcActuatorBank {
 public:
  // One block per link from LinkStateSpace. Throws std::invalid_argument
  // naming the link and field on a bad configuration.
  static std::unique_ptr<IpmcActuatorBank> Create(
      std::vector<IpmcLinkParams> links, CvodeOptions options = {},
      ActuatorIntegration integration = ActuatorIntegration::kCvode);

  // One arbitrary SISO block per "link" (e.g. a bare Oustaloup block).
  // Needs at least one block and at least one state in total; throws
  // std::invalid_argument otherwise or on a malformed block.
  static std::unique_ptr<IpmcActuatorBank> CreateFromStateSpace(
      std::vector<StateSpace> blocks, CvodeOptions options = {},
      ActuatorIntegration integration = ActuatorIntegration::kCvode);

  ~IpmcActuatorBank();
  IpmcActuatorBank(const IpmcActuatorBank&) = delete;
  IpmcActuatorBank& operator=(const IpmcActuatorBank&) = delete;

  int Links() const;
  int States() const;

  // One voltage per link [V]. A non-finite value throws
  // std::invalid_argument naming the link; so does a wrong count. Held
  // until changed.
  void SetVoltages(const std::vector<double>& voltage_V);
  const std::vector<double>& Voltages_V() const;

  // Integrates from Time_s() to t_s (>= Time_s(), finite; otherwise
  // std::invalid_argument) with the held voltages. Throws
  // std::runtime_error naming the time, the link with the largest local
  // error estimate and the CVODE flag if CVODE fails.
  void AdvanceTo(double t_s);

  // y_q = c_q x_q + d_q u_q [mm], one per link.
  // The same for one link (0-based), without allocating.
  double FreeTipDeflection_mm(int link) const;
  std::vector<double> FreeTipDeflection_mm() const;

  double Time_s() const;

  // Zero state at time t0_s (finite); the held voltages are kept.
  void Reset(double t0_s = 0);

  // x = `state` at time t_s, the held voltages kept. Throws
  // std::invalid_argument unless t_s is finite and `state` holds States()
  // finite values.
  void SetState(double t_s, const Eigen::VectorXd& state);

  // Makes the next AdvanceTo restart CVODE at Time_s() from State(),
  // discarding its internal steps past Time_s() and the times of earlier
  // voltage changes (from which the bank expects the next one). From a
  // restart the integration depends only on (Time_s(), State(),
  // Voltages_V()) and the times asked for and at which voltages change, so
  // two banks of the same links set to the same triple (SetState,
  // SetVoltages) give identical numbers. Reset and SetState imply it.
  void Restart();

  // The augmented Oustaloup state x at Time_s(), links in order.
  const Eigen::VectorXd& State() const;

  // Diagnostics: CVODE internal steps since creation (kExact: the exact
  // advances), and the number of re-initialisations (restarts: voltage
  // changes CVODE does not continue across, resets, held voltages going
  // back to the plain form; kExact: none).
  long InternalSteps() const;
  long Reinitialisations() const;

 private:
  struct Impl;
  explicit IpmcActuatorBank(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace ipmc

#endif  // IPMC_SWIM_PLUGIN_IPMC_ACTUATOR_BANK_H_
