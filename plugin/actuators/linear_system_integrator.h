// How the IPMC actuator bank (plugin/actuators/ipmc_actuator_bank.h)
// advances its stacked linear system (plugin/actuators/stacked_linear_system.h),
// dx/dt = A x + B u with u held between changes. Two implementations:
// the exact one under the zero-order hold
// (plugin/actuators/zero_order_hold_integrator.h) and SUNDIALS CVODE
// (plugin/actuators/cvode_integrator.h). Each owns the time, the state x
// and the workspace it integrates with; the bank checks every argument
// before passing it on.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace ipmc {

// A time difference an integrator cannot resolve: a few ulps of t. An
// advance over no more than this leaves the state unchanged.
inline double UnresolvableInterval_s(double a_s, double b_s) {
  return 8.0 * std::numeric_limits<double>::epsilon() *
         std::max({1.0, std::abs(a_s), std::abs(b_s)});
}

class LinearSystemIntegrator {
 public:
  // How the next Advance starts after SetState: as a new integrator does
  // (kFromRest: creation, the bank's Reset), or going on from a state set
  // or saved (kFromSetState: the bank's SetState and Restart), the same
  // for the integrator saved and the one restored.
  enum class Start { kFromRest, kFromSetState };

  virtual ~LinearSystemIntegrator() = default;

  double Time_s() const { return time_s_; }
  const Eigen::VectorXd& State() const { return state_; }

  // x = state at t_s; the next Advance starts afresh as `start` says and
  // takes the held input as it is then (no input change at t_s).
  void SetState(double t_s, const Eigen::VectorXd& state, Start start);
  // The next Advance starts afresh from (Time_s(), State()), kFromSetState.
  void Restart();
  // The held input changed at Time_s() (one value per link).
  virtual void HeldInputChanged(const std::vector<double>& held_input_V) = 0;
  // Integrates from Time_s() to t1_s (more than UnresolvableInterval_s
  // later) with held_input_V held; sets Time_s() and State(). May throw
  // std::runtime_error, leaving Time_s() and State() at the last point
  // reached.
  virtual void Advance(double t1_s, const std::vector<double>& held_input_V) = 0;

  // Diagnostics: internal steps (or exact advances) since creation, and
  // restarts of the integration (none for the exact one).
  virtual long InternalSteps() const = 0;
  virtual long Reinitialisations() const = 0;

 protected:
  explicit LinearSystemIntegrator(int states) : state_(Eigen::VectorXd::Zero(states)) {}
  // What SetState and Restart ask of the next Advance.
  virtual void StartAfresh(Start start) = 0;

  double time_s_ = 0;
  Eigen::VectorXd state_;
};

inline void LinearSystemIntegrator::SetState(double t_s, const Eigen::VectorXd& state,
                                             Start start) {
  state_ = state;
  time_s_ = t_s;
  StartAfresh(start);
}

inline void LinearSystemIntegrator::Restart() { StartAfresh(Start::kFromSetState); }

}  // namespace ipmc
