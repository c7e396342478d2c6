// The IPMC actuators of a flagellum: their stacked linear system and one
// integrator for it.
//
// Each link q is a SISO state-space block (sim/linear/ipmc_link_model.h), voltage
// u_q [V] -> free tip deflection y_q [mm], stacked once into
// (plugin/actuators/stacked_linear_system.h)
//
//   dx/dt = A x + B u,   y_q = c_q x_q + d_q u_q,
//
// u held constant between SetVoltages calls that change it. The bank
// checks its callers' arguments, holds the voltages and hands the
// integration to one LinearSystemIntegrator
// (plugin/actuators/linear_system_integrator.h), chosen at creation:
//  - ActuatorIntegration::kExact: the ODE advanced over each AdvanceTo
//    interval by its zero-order-hold matrices, exact to rounding since the
//    voltages are held between SetVoltages calls
//    (plugin/actuators/zero_order_hold_integrator.h); CVODE is not created.
//  - ActuatorIntegration::kCvode: SUNDIALS CVODE, variable-order BDF with
//    an exact Newton solve and a change of variables that steps across the
//    voltage changes without restarting (plugin/actuators/cvode_integrator.h,
//    where the method and its measured cost are described).
#ifndef IPMC_SWIM_PLUGIN_IPMC_ACTUATOR_BANK_H_
#define IPMC_SWIM_PLUGIN_IPMC_ACTUATOR_BANK_H_

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "sim/linear/state_space.h"
#include "plugin/actuators/cvode_options.h"
#include "sim/linear/ipmc_link_model.h"
#include "plugin/actuators/linear_system_integrator.h"
#include "plugin/actuators/stacked_linear_system.h"

namespace ipmc {

// How a bank advances its state: by CVODE, or exactly, the voltages held
// constant over each AdvanceTo interval, by the interval's matrix
// exponential (plugin/actuators/zero_order_hold.h; the options' tolerances
// then play no part).
enum class ActuatorIntegration { kCvode, kExact };

// "cvode" / "exact"; ParseActuatorIntegration returns nullopt for any
// other word.
const char* ActuatorIntegrationName(ActuatorIntegration integration);
std::optional<ActuatorIntegration> ParseActuatorIntegration(const std::string& word);

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
  IpmcActuatorBank(std::unique_ptr<const StackedLinearSystem> system,
                   ActuatorIntegration integration, const CvodeOptions& options);

  // Fixed by the model; the integrator reads it, so it is declared first
  // and outlives it.
  const std::unique_ptr<const StackedLinearSystem> system_;
  std::vector<double> voltage_V_;  // held, one per link
  std::unique_ptr<LinearSystemIntegrator> integrator_;
};

}  // namespace ipmc

#endif  // IPMC_SWIM_PLUGIN_IPMC_ACTUATOR_BANK_H_
