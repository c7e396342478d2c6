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
// while the input is unchanged. When SetVoltages changes a value, the next
// AdvanceTo first re-initialises CVODE at the current time from the current
// state (CVodeReInit), discarding any internal step taken past that instant
// with the old input; an input that does not change costs nothing.
//
// Cost (3 paper G1 links, 30 states, AdvanceTo every 0.1 ms, voltages
// changed every 1 ms, default options): about 1.8 us per AdvanceTo, of
// which most is the restart after each change; 0.15 us with held voltages.
// The bank replaces the serial N_Vector kernels of the vectors CVODE uses
// with equivalent loops compiled with the project (plugin/actuators/serial_kernels.h).
#ifndef IPMC_SWIM_PLUGIN_IPMC_ACTUATOR_BANK_H_
#define IPMC_SWIM_PLUGIN_IPMC_ACTUATOR_BANK_H_

#include <memory>
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
      std::vector<IpmcLinkParams> links, CvodeOptions options = {});

  // One arbitrary SISO block per "link" (e.g. a bare Oustaloup block).
  // Needs at least one block and at least one state in total; throws
  // std::invalid_argument otherwise or on a malformed block.
  static std::unique_ptr<IpmcActuatorBank> CreateFromStateSpace(
      std::vector<StateSpace> blocks, CvodeOptions options = {});

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

  // Makes the next AdvanceTo restart CVODE at Time_s() from State(), as a
  // voltage change does, discarding its internal steps past Time_s(). From
  // a restart the integration depends only on (Time_s(), State(),
  // Voltages_V()) and the times asked for, so two banks of the same links
  // set to the same triple (SetState, SetVoltages) give identical numbers.
  // Reset, SetState and a voltage change imply it.
  void Restart();

  // The augmented Oustaloup state x at Time_s(), links in order.
  const Eigen::VectorXd& State() const;

  // Diagnostics: CVODE internal steps since creation, and the number of
  // re-initialisations (input changes and resets).
  long InternalSteps() const;
  long Reinitialisations() const;

 private:
  struct Impl;
  explicit IpmcActuatorBank(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace ipmc

#endif  // IPMC_SWIM_PLUGIN_IPMC_ACTUATOR_BANK_H_
