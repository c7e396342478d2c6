#include "controllers/fractional_integrator.h"
#include "controllers/paper_eq15.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include <unsupported/Eigen/MatrixFunctions>

#include "sim/base/error.h"
#include "sim/base/numbers.h"

namespace ipmc {
namespace {

[[noreturn]] void ThrowField(const char* field, const std::string& rule,
                             const std::string& got) {
  throw FieldError(std::string("FractionalIntegrator.Config.") + field +
                       " must be " + rule + ", got " + got,
                   field, rule);
}

}  // namespace

DiscreteStateSpace DiscretizeZeroOrderHold(const StateSpace& continuous,
                                           double sample_period_s) {
  continuous.Validate("DiscretizeZeroOrderHold: continuous system");
  if (!std::isfinite(sample_period_s) || !(sample_period_s > 0)) {
    throw std::invalid_argument(
        "DiscretizeZeroOrderHold: sample_period_s must be finite and > 0, "
        "got " +
        FormatDouble(sample_period_s));
  }
  const int n = continuous.States();
  DiscreteStateSpace discrete;
  discrete.c = continuous.c;
  discrete.d = continuous.d;
  discrete.sample_period_s = sample_period_s;
  if (n == 0) {
    discrete.a = Eigen::MatrixXd::Zero(0, 0);
    discrete.b = Eigen::MatrixXd::Zero(0, 1);
    return discrete;
  }
  Eigen::MatrixXd augmented = Eigen::MatrixXd::Zero(n + 1, n + 1);
  augmented.topLeftCorner(n, n) = continuous.a * sample_period_s;
  augmented.topRightCorner(n, 1) = continuous.b * sample_period_s;
  const Eigen::MatrixXd exponential = augmented.exp();
  discrete.a = exponential.topLeftCorner(n, n);
  discrete.b = exponential.topRightCorner(n, 1);
  if (!discrete.a.allFinite() || !discrete.b.allFinite()) {
    throw std::invalid_argument(
        "DiscretizeZeroOrderHold: matrix exponential is not finite (sample "
        "period " +
        FormatDouble(sample_period_s) + " s)");
  }
  return discrete;
}

const char* FractionalRealisationName(FractionalRealisation realisation) {
  return realisation == FractionalRealisation::kEq15 ? "eq15" : "oustaloup";
}

std::optional<FractionalRealisation> ParseFractionalRealisation(const std::string& word) {
  for (FractionalRealisation realisation :
       {FractionalRealisation::kOustaloup, FractionalRealisation::kEq15}) {
    if (word == FractionalRealisationName(realisation)) return realisation;
  }
  return std::nullopt;
}

void FractionalIntegrator::Config::Validate() const {
  if (!std::isfinite(gain) || gain < 0) {
    ThrowField("gain", "finite and >= 0", FormatDouble(gain));
  }
  if (!std::isfinite(order) || !(order > 0) || order > 1) {
    ThrowField("order", "in (0, 1]", FormatDouble(order));
  }
  if (oustaloup_n < 1 || oustaloup_n > kMaxOustaloupPairs) {
    ThrowField("oustaloup_n", "in [1, " + std::to_string(kMaxOustaloupPairs) + "]",
               std::to_string(oustaloup_n));
  }
  if (!std::isfinite(w_low_rad_s) || !(w_low_rad_s > 0)) {
    ThrowField("w_low_rad_s", "finite and > 0", FormatDouble(w_low_rad_s));
  }
  if (!std::isfinite(w_high_rad_s) || !(w_high_rad_s > w_low_rad_s)) {
    ThrowField("w_high_rad_s",
               "finite and > w_low_rad_s (" + FormatDouble(w_low_rad_s) + ")",
               FormatDouble(w_high_rad_s));
  }
  if (!std::isfinite(sample_period_s) || !(sample_period_s > 0)) {
    ThrowField("sample_period_s", "finite and > 0",
               FormatDouble(sample_period_s));
  }
  if (clamp_enabled && (!std::isfinite(v_max) || !(v_max > 0))) {
    ThrowField("v_max", "finite and > 0", FormatDouble(v_max));
  }
  if (realisation != FractionalRealisation::kOustaloup &&
      realisation != FractionalRealisation::kEq15) {
    ThrowField("realisation", "kOustaloup or kEq15",
               std::to_string(static_cast<int>(realisation)));
  }
}

namespace {

// K s^-lambda by Oustaloup, or eq. 15 as printed.
StateSpace ContinuousRealisation(const FractionalIntegrator::Config& config) {
  if (config.realisation == FractionalRealisation::kEq15) return Eq15StateSpace();
  OustaloupConfig oustaloup;
  oustaloup.order = -config.order;
  oustaloup.w_low_rad_s = config.w_low_rad_s;
  oustaloup.w_high_rad_s = config.w_high_rad_s;
  oustaloup.n = config.oustaloup_n;
  oustaloup.variant = config.variant;
  return Series(OustaloupStateSpace(oustaloup), Gain(config.gain));
}

}  // namespace

FractionalIntegrator::FractionalIntegrator(const Config& config)
    : config_(config) {
  config_.Validate();
  continuous_ = ContinuousRealisation(config_);
  discrete_ = DiscretizeZeroOrderHold(continuous_, config_.sample_period_s);
  state_ = Eigen::VectorXd::Zero(continuous_.States());
}

double FractionalIntegrator::Update(double error) {
  if (!std::isfinite(error)) {
    throw std::invalid_argument(
        "FractionalIntegrator::Update: error must be finite, got " +
        FormatDouble(error));
  }
  double output = discrete_.d(0, 0) * error;
  if (state_.size() > 0) output += (discrete_.c * state_)(0, 0);
  bool hold_state = false;
  if (config_.clamp_enabled) {
    // Conditional integration: hold the state while saturated if the error
    // would push the output further into the limit.
    hold_state = std::abs(output) > config_.v_max && error * output > 0;
    output = std::clamp(output, -config_.v_max, config_.v_max);
  }
  if (!hold_state && state_.size() > 0) {
    state_ = discrete_.a * state_ + discrete_.b * error;
  }
  last_output_ = output;
  return output;
}

void FractionalIntegrator::Reset() {
  state_.setZero();
  last_output_ = 0.0;
}

std::complex<double> FractionalIntegrator::EvaluateExact(
    std::complex<double> s) const {
  return config_.gain * std::pow(s, -config_.order);
}

std::complex<double> FractionalIntegrator::Evaluate(
    std::complex<double> s) const {
  return continuous_.Evaluate(s);
}

}  // namespace ipmc
