#include "controllers/pid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "sim/base/error.h"
#include "sim/base/numbers.h"

namespace ipmc {
namespace {

void RequireNonNegative(const char* field, double value) {
  if (!std::isfinite(value) || value < 0) {
    throw FieldError(std::string("PidController.Config.") + field +
                         " must be finite and >= 0, got " + FormatDouble(value),
                     field, "finite and >= 0");
  }
}

void RequirePositive(const char* field, double value) {
  if (!std::isfinite(value) || !(value > 0)) {
    throw FieldError(std::string("PidController.Config.") + field +
                         " must be finite and > 0, got " + FormatDouble(value),
                     field, "finite and > 0");
  }
}

}  // namespace

void PidController::Config::Validate() const {
  RequireNonNegative("kp", kp);
  RequireNonNegative("ki", ki);
  RequireNonNegative("kd", kd);
  RequireNonNegative("derivative_filter_time_s", derivative_filter_time_s);
  RequirePositive("sample_period_s", sample_period_s);
  if (clamp_enabled) RequirePositive("v_max", v_max);
}

PidController::PidController(const Config& config) : config_(config) {
  config_.Validate();
}

double PidController::Update(double error) {
  if (!std::isfinite(error)) {
    throw std::invalid_argument(
        "PidController::Update: error must be finite, got " +
        FormatDouble(error));
  }
  const double period = config_.sample_period_s;
  const double filter = config_.derivative_filter_time_s;
  derivative_ =
      (filter * derivative_ + config_.kd * (error - previous_error_)) /
      (filter + period);
  previous_error_ = error;

  const double proportional = config_.kp * error;
  const double increment = config_.ki * period * error;
  double integral = integral_ + increment;
  double output = proportional + integral + derivative_;
  if (config_.clamp_enabled) {
    // Conditional integration: the integral advances into saturation only
    // as far as the limit, and holds if the output is already beyond it.
    const double headroom =
        std::copysign(config_.v_max, increment) - proportional - derivative_;
    if (increment > 0 && output > config_.v_max) {
      integral = std::max(integral_, std::min(integral, headroom));
    } else if (increment < 0 && output < -config_.v_max) {
      integral = std::min(integral_, std::max(integral, headroom));
    }
    output = std::clamp(proportional + integral + derivative_, -config_.v_max,
                        config_.v_max);
  }
  integral_ = integral;
  last_output_ = output;
  return output;
}

void PidController::Reset() {
  integral_ = 0.0;
  derivative_ = 0.0;
  previous_error_ = 0.0;
  last_output_ = 0.0;
}

std::complex<double> PidController::Evaluate(std::complex<double> s) const {
  return config_.kp + config_.ki / s +
         config_.kd * s / (config_.derivative_filter_time_s * s + 1.0);
}

double PidController::DerivativeFilterTimeFromN(double kp, double kd,
                                                double n) {
  if (!std::isfinite(kp) || !(kp > 0)) {
    throw std::invalid_argument(
        "PidController::DerivativeFilterTimeFromN: kp must be finite and > 0, "
        "got " +
        FormatDouble(kp));
  }
  if (!std::isfinite(kd) || kd < 0) {
    throw std::invalid_argument(
        "PidController::DerivativeFilterTimeFromN: kd must be finite and >= "
        "0, got " +
        FormatDouble(kd));
  }
  if (!std::isfinite(n) || !(n > 0)) {
    throw std::invalid_argument(
        "PidController::DerivativeFilterTimeFromN: n must be finite and > 0, "
        "got " +
        FormatDouble(n));
  }
  return kd / (kp * n);
}

}  // namespace ipmc
