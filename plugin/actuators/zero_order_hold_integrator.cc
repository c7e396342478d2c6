#include "plugin/actuators/zero_order_hold_integrator.h"

#include <utility>

namespace ipmc {
namespace {

ZeroOrderHold HoldOf(const StackedLinearSystem& system) {
  std::vector<Eigen::MatrixXd> a;
  std::vector<Eigen::VectorXd> b;
  for (const LinkBlock& block : system.Blocks()) {
    a.push_back(block.a);
    b.push_back(block.b);
  }
  return ZeroOrderHold(std::move(a), std::move(b));
}

}  // namespace

ZeroOrderHoldIntegrator::ZeroOrderHoldIntegrator(const StackedLinearSystem& system)
    : LinearSystemIntegrator(system.States()), hold_(HoldOf(system)) {}

void ZeroOrderHoldIntegrator::Advance(double t1_s, const std::vector<double>& held_input_V) {
  hold_.Advance(t1_s - time_s_, held_input_V, &state_);
  time_s_ = t1_s;
}

}  // namespace ipmc
