#include "plugin/actuators/ipmc_actuator_bank.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "plugin/actuators/cvode_integrator.h"
#include "plugin/actuators/zero_order_hold_integrator.h"

namespace ipmc {

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
  auto system = std::make_unique<const StackedLinearSystem>(blocks);
  return std::unique_ptr<IpmcActuatorBank>(
      new IpmcActuatorBank(std::move(system), integration, options));
}

IpmcActuatorBank::IpmcActuatorBank(std::unique_ptr<const StackedLinearSystem> system,
                                   ActuatorIntegration integration, const CvodeOptions& options)
    : system_(std::move(system)), voltage_V_(system_->Blocks().size(), 0.0) {
  if (integration == ActuatorIntegration::kExact) {
    integrator_ = std::make_unique<ZeroOrderHoldIntegrator>(*system_);
  } else {
    integrator_ = std::make_unique<CvodeIntegrator>(*system_, options);
  }
}

IpmcActuatorBank::~IpmcActuatorBank() = default;

int IpmcActuatorBank::Links() const { return system_->Links(); }

int IpmcActuatorBank::States() const { return system_->States(); }

void IpmcActuatorBank::SetVoltages(const std::vector<double>& voltage_V) {
  if (voltage_V.size() != voltage_V_.size()) {
    std::ostringstream out;
    out << "ipmc actuator: voltage_V needs " << voltage_V_.size()
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
  bool changed = false;
  for (std::size_t q = 0; q < voltage_V.size(); ++q) {
    if (voltage_V[q] == voltage_V_[q]) continue;
    voltage_V_[q] = voltage_V[q];
    changed = true;
  }
  if (changed) integrator_->HeldInputChanged(voltage_V_);
}

const std::vector<double>& IpmcActuatorBank::Voltages_V() const { return voltage_V_; }

void IpmcActuatorBank::AdvanceTo(double t_s) {
  const double time_s = integrator_->Time_s();
  if (!std::isfinite(t_s) || t_s < time_s) {
    std::ostringstream out;
    out.precision(17);
    out << "ipmc actuator: AdvanceTo needs a finite t_s >= Time_s() = " << time_s << " s (got "
        << t_s << ")";
    throw std::invalid_argument(out.str());
  }
  // No integrator resolves an interval below a few ulps of t; such a step
  // leaves the state unchanged.
  if (t_s - time_s <= UnresolvableInterval_s(t_s, time_s)) return;
  integrator_->Advance(t_s, voltage_V_);
}

double IpmcActuatorBank::FreeTipDeflection_mm(int link) const {
  return system_->Output(link, integrator_->State(), voltage_V_.at(link));
}

std::vector<double> IpmcActuatorBank::FreeTipDeflection_mm() const {
  std::vector<double> out(voltage_V_.size());
  for (std::size_t q = 0; q < out.size(); ++q) out[q] = FreeTipDeflection_mm(static_cast<int>(q));
  return out;
}

double IpmcActuatorBank::Time_s() const { return integrator_->Time_s(); }

void IpmcActuatorBank::Reset(double t0_s) {
  if (!std::isfinite(t0_s)) {
    std::ostringstream out;
    out << "ipmc actuator: Reset needs a finite t0_s (got " << t0_s << ")";
    throw std::invalid_argument(out.str());
  }
  integrator_->SetState(t0_s, Eigen::VectorXd::Zero(system_->States()),
                        LinearSystemIntegrator::Start::kFromRest);
}

void IpmcActuatorBank::SetState(double t_s, const Eigen::VectorXd& state) {
  if (!std::isfinite(t_s)) {
    std::ostringstream out;
    out << "ipmc actuator: SetState needs a finite t_s (got " << t_s << ")";
    throw std::invalid_argument(out.str());
  }
  if (state.size() != system_->States()) {
    std::ostringstream out;
    out << "ipmc actuator: state needs " << system_->States() << " values (got " << state.size()
        << ")";
    throw std::invalid_argument(out.str());
  }
  if (!state.allFinite()) {
    throw std::invalid_argument("ipmc actuator: state values must be finite");
  }
  integrator_->SetState(t_s, state, LinearSystemIntegrator::Start::kFromSetState);
}

void IpmcActuatorBank::Restart() { integrator_->Restart(); }

const Eigen::VectorXd& IpmcActuatorBank::State() const { return integrator_->State(); }

long IpmcActuatorBank::InternalSteps() const { return integrator_->InternalSteps(); }

long IpmcActuatorBank::Reinitialisations() const { return integrator_->Reinitialisations(); }

}  // namespace ipmc
