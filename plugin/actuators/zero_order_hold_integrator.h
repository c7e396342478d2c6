// The stacked linear system (plugin/actuators/stacked_linear_system.h)
// integrated exactly under the zero-order hold: each Advance is
// x <- Phi(h) x + Gamma(h) u over the interval h, the input held
// (plugin/actuators/zero_order_hold.h: the equation and its sources).
// Exact to rounding, with no error control, no internal steps and no
// restarts: the start of an advance plays no part.
#pragma once

#include <vector>

#include "plugin/actuators/linear_system_integrator.h"
#include "plugin/actuators/stacked_linear_system.h"
#include "plugin/actuators/zero_order_hold.h"

namespace ipmc {

class ZeroOrderHoldIntegrator : public LinearSystemIntegrator {
 public:
  explicit ZeroOrderHoldIntegrator(const StackedLinearSystem& system);

  void HeldInputChanged(const std::vector<double>& /*held_input_V*/) override {}
  void Advance(double t1_s, const std::vector<double>& held_input_V) override;

  // The exact advances made; no restarts.
  long InternalSteps() const override { return hold_.Advances(); }
  long Reinitialisations() const override { return 0; }

 private:
  void StartAfresh(Start /*start*/) override {}

  ZeroOrderHold hold_;
};

}  // namespace ipmc
