#include "sim/identify/controller_design.h"

#include <cmath>
#include <complex>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>

#include <nlopt.hpp>

#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "controllers/fractional_integrator.h"
#include "controllers/pid.h"

namespace ipmc {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// The phase of P is unwrapped from w_c / kUnwrapDecadesFactor up to w_c.
constexpr double kUnwrapStartFactor = 1e-4;
constexpr int kUnwrapPointsPerDecade = 100;
// A loop whose output leaves this multiple of the step has diverged.
constexpr double kDivergedOutput = 1e6;
// Horizon and sample period must agree to this relative slack.
constexpr double kHorizonSlack = 1e-9;

[[noreturn]] void Throw(const std::string& where, const std::string& message) {
  throw std::invalid_argument(where + ": " + message);
}

double FiniteOr(double value) { return std::isfinite(value) ? value : kInfinity; }

Eigen::VectorXd LogGains(const PidGains& gains) {
  Eigen::VectorXd x(3);
  x << std::log(gains.kp), std::log(gains.ki), std::log(gains.kd);
  return x;
}

PidGains GainsFromLog(const Eigen::VectorXd& x) {
  return {std::exp(x(0)), std::exp(x(1)), std::exp(x(2))};
}

void CheckGains(const char* where, const PidGains& gains, bool strictly_positive) {
  const std::pair<const char*, double> terms[] = {
      {"kp", gains.kp}, {"ki", gains.ki}, {"kd", gains.kd}};
  for (const auto& [name, value] : terms) {
    if (!std::isfinite(value) || value < 0 || (strictly_positive && value == 0)) {
      Throw(where, std::string(name) + " must be finite and " + (strictly_positive ? ">" : ">=") +
                       " 0 (got " + FormatDouble(value) + ")");
    }
  }
}

}  // namespace

// ------------------------------------------------ fractional integrator ---

FractionalIntegratorDesign DesignFractionalIntegrator(const FrequencyFunction& plant,
                                                      double crossover_rad_s,
                                                      double phase_margin_deg) {
  const char* where = "fractional integrator design";
  if (!std::isfinite(crossover_rad_s) || !(crossover_rad_s > 0)) {
    Throw(where, "crossover_rad_s must be finite and > 0 (got " + FormatDouble(crossover_rad_s) +
                     ")");
  }
  if (!std::isfinite(phase_margin_deg) || !(phase_margin_deg > 0) || !(phase_margin_deg < 180)) {
    Throw(where, "phase_margin_deg must be in (0, 180) (got " + FormatDouble(phase_margin_deg) +
                     ")");
  }
  if (!plant) Throw(where, "plant is empty");
  FrequencyGrid grid;
  grid.w_low_rad_s = kUnwrapStartFactor * crossover_rad_s;
  grid.w_high_rad_s = crossover_rad_s;
  grid.points_per_decade = kUnwrapPointsPerDecade;
  const BodeData bode = ComputeBode(plant, grid);

  FractionalIntegratorDesign design;
  design.plant_phase_deg = bode.phase_deg.back();
  design.plant_magnitude = std::abs(plant(crossover_rad_s));
  design.order = (design.plant_phase_deg + 180.0 - phase_margin_deg) / 90.0;
  if (!(design.order > 0) || design.order > 1) {
    throw std::domain_error(std::string(where) + ": phase margin " +
                            FormatDouble(phase_margin_deg) + " deg at " +
                            FormatDouble(crossover_rad_s) + " rad/s needs lambda = " +
                            FormatDouble(design.order) + ", outside (0, 1] (plant phase " +
                            FormatDouble(design.plant_phase_deg) + " deg)");
  }
  design.gain = std::pow(crossover_rad_s, design.order) / design.plant_magnitude;
  return design;
}

// ----------------------------------------------------------- Nelder-Mead ---

void NelderMeadOptions::Validate() const {
  const char* where = "nelder-mead";
  if (max_evaluations < 1) {
    Throw(where, "max_evaluations must be >= 1 (got " + std::to_string(max_evaluations) + ")");
  }
  if (!std::isfinite(f_tolerance) || f_tolerance < 0) {
    Throw(where, "f_tolerance must be finite and >= 0 (got " + FormatDouble(f_tolerance) + ")");
  }
  if (!std::isfinite(x_tolerance) || x_tolerance < 0) {
    Throw(where, "x_tolerance must be finite and >= 0 (got " + FormatDouble(x_tolerance) + ")");
  }
  if (!std::isfinite(initial_step) || initial_step == 0) {
    Throw(where, "initial_step must be finite and != 0 (got " + FormatDouble(initial_step) + ")");
  }
}

namespace {

// What the NLopt objective needs: f, the evaluation count, and the first
// exception f or the start check raised (NLopt's C core cannot carry it).
struct NelderMeadObjective {
  const std::function<double(const Eigen::VectorXd&)>* f = nullptr;
  nlopt::opt* optimizer = nullptr;
  int evaluations = 0;
  std::exception_ptr error;
};

double EvaluateForNlopt(const std::vector<double>& x, std::vector<double>& /*gradient*/,
                        void* data) {
  auto& objective = *static_cast<NelderMeadObjective*>(data);
  try {
    ++objective.evaluations;
    const double value =
        FiniteOr((*objective.f)(Eigen::Map<const Eigen::VectorXd>(x.data(), x.size())));
    // NLopt evaluates the start first.
    if (objective.evaluations == 1 && !std::isfinite(value)) {
      Throw("nelder-mead", "f is not finite at the start");
    }
    return value;
  } catch (...) {
    objective.error = std::current_exception();
    objective.optimizer->force_stop();
    return kInfinity;
  }
}

bool IsConvergence(nlopt::result code) {
  return code == nlopt::SUCCESS || code == nlopt::FTOL_REACHED || code == nlopt::XTOL_REACHED;
}

}  // namespace

NelderMeadResult MinimizeNelderMead(const std::function<double(const Eigen::VectorXd&)>& f,
                                    const Eigen::VectorXd& start,
                                    const NelderMeadOptions& options) {
  const char* where = "nelder-mead";
  options.Validate();
  const int n = static_cast<int>(start.size());
  if (n == 0) Throw(where, "start is empty");
  if (!start.allFinite()) Throw(where, "start is not finite");
  if (options.max_evaluations < n + 1) {
    Throw(where, "max_evaluations must be >= n + 1 = " + std::to_string(n + 1) + " (got " +
                     std::to_string(options.max_evaluations) + ")");
  }

  nlopt::opt optimizer(nlopt::LN_NELDERMEAD, static_cast<unsigned>(n));
  NelderMeadObjective objective;
  objective.f = &f;
  objective.optimizer = &optimizer;
  optimizer.set_min_objective(EvaluateForNlopt, &objective);
  optimizer.set_initial_step(options.initial_step);
  optimizer.set_xtol_abs(options.x_tolerance);
  optimizer.set_ftol_abs(options.f_tolerance);
  optimizer.set_maxeval(options.max_evaluations);

  std::vector<double> x(start.data(), start.data() + n);
  double value = kInfinity;
  nlopt::result code = nlopt::FAILURE;
  try {
    code = optimizer.optimize(x, value);
  } catch (const nlopt::forced_stop&) {
    if (objective.error) std::rethrow_exception(objective.error);
    throw;
  } catch (const nlopt::roundoff_limited&) {
    code = nlopt::ROUNDOFF_LIMITED;  // x and value hold the best point
  }
  NelderMeadResult result;
  result.x = Eigen::Map<const Eigen::VectorXd>(x.data(), n);
  result.value = value;
  result.evaluations = objective.evaluations;
  result.converged = IsConvergence(code);
  return result;
}

// ---------------------------------------------------------- PID tuning ---

std::vector<PidGains> DefaultPidStarts() {
  return {PidGains{}, {1.0, 10.0, 0.1}, {20.0, 200.0, 2.0}, {2.0, 100.0, 1.0}, {30.0, 20.0, 0.05}};
}

void PidTuningOptions::Validate() const {
  const char* where = "pid tuning";
  reference.Validate();
  if (!std::isfinite(sample_period_s) || !(sample_period_s > 0)) {
    Throw(where, "sample_period_s must be finite and > 0 (got " + FormatDouble(sample_period_s) +
                     ")");
  }
  if (!std::isfinite(horizon_s) || !(horizon_s > 0)) {
    Throw(where, "horizon_s must be finite and > 0 (got " + FormatDouble(horizon_s) + ")");
  }
  const double samples = horizon_s / sample_period_s;
  if (std::abs(samples - std::round(samples)) > kHorizonSlack * samples || samples < 2 ||
      samples > 1e8) {
    Throw(where, "horizon_s must be a whole number (2 to 1e8) of sample periods " +
                     FormatDouble(sample_period_s) + " s (got " + FormatDouble(horizon_s) + ")");
  }
  for (const PidGains& start : starts) CheckGains("pid tuning: starts", start, true);
  search.Validate();
}

PidStepCost::PidStepCost(const StateSpace& plant, const PidTuningOptions& options) {
  options.Validate();
  plant.Validate("pid tuning: plant");
  hold_ = DiscretizeZeroOrderHold(plant, options.sample_period_s);
  sample_period_s_ = options.sample_period_s;
  derivative_filter_s_ = options.derivative_filter_s;
  samples_ = static_cast<int>(std::lround(options.horizon_s / options.sample_period_s));
  const ReferenceModel model(options.reference);
  reference_.resize(samples_ + 1);
  weight_.resize(samples_ + 1);
  constexpr int kStopCheckSamples = 500;  // the reference's samples take ~0.1 ms each
  for (int k = 0; k <= samples_; ++k) {
    if (options.check_stop && k % kStopCheckSamples == 0) options.check_stop();
    const double t = k * sample_period_s_;
    reference_[k] = model.StepResponse(t);
    const double trapezoid = (k == 0 || k == samples_) ? 0.5 : 1.0;
    weight_[k] = trapezoid * sample_period_s_ * (0.5 + 0.5 * t);
  }
}

double PidStepCost::operator()(const PidGains& gains) const {
  CheckGains("pid tuning", gains, false);
  PidController::Config config;
  config.kp = gains.kp;
  config.ki = gains.ki;
  config.kd = gains.kd;
  config.sample_period_s = sample_period_s_;
  config.derivative_filter_time_s = derivative_filter_s_;
  config.clamp_enabled = false;
  PidController pid(config);

  HeldPlant plant(hold_);
  double cost = 0.0;
  for (int k = 0; k < samples_; ++k) {
    const double measured = plant.Output();  // y(t_k^-), before the new voltage
    if (!std::isfinite(measured) || std::abs(measured) > kDivergedOutput) return kInfinity;
    plant.Hold(pid.Update(1.0 - measured));
    cost += weight_[k] * std::abs(reference_[k] - plant.Output());
    plant.Advance();
  }
  const double last = plant.Output();
  if (!std::isfinite(last) || std::abs(last) > kDivergedOutput) return kInfinity;
  cost += weight_[samples_] * std::abs(reference_[samples_] - last);
  return cost;
}

PidTuningResult TunePid(const StateSpace& plant, const PidTuningOptions& options) {
  const PidStepCost cost(plant, options);
  const std::vector<PidGains> starts =
      options.starts.empty() ? DefaultPidStarts() : options.starts;
  PidTuningResult result;
  result.cost = kInfinity;
  for (const PidGains& start : starts) {
    PidTuningRun run;
    run.start = start;
    run.start_cost = cost(start);
    if (!std::isfinite(run.start_cost)) {
      Throw("pid tuning", "the loop diverges at the start Kp = " + FormatDouble(start.kp) +
                              ", Ki = " + FormatDouble(start.ki) + ", Kd = " +
                              FormatDouble(start.kd));
    }
    const NelderMeadResult search = MinimizeNelderMead(
        [&](const Eigen::VectorXd& x) {
          if (options.check_stop) options.check_stop();
          return cost(GainsFromLog(x));
        },
        LogGains(start), options.search);
    run.gains = GainsFromLog(search.x);
    run.cost = search.value;
    run.evaluations = search.evaluations;
    run.converged = search.converged;
    if (run.cost < result.cost) {
      result.cost = run.cost;
      result.gains = run.gains;
    }
    result.runs.push_back(run);
  }
  return result;
}

StateSpace AccurateLinkPlant(IpmcLinkParams params) {
  params.integrator.w_low_rad_s = kAccurateBandLow_rad_s;
  params.integrator.w_high_rad_s = kAccurateBandHigh_rad_s;
  params.integrator.n = kAccurateOustaloupPairs;
  return LinkStateSpace(params);
}

FractionalLoopDesign DesignFractionalLoop(const FrequencyFunction& plant, double crossover_rad_s,
                                          double phase_margin_deg) {
  FractionalLoopDesign result;
  result.design = DesignFractionalIntegrator(plant, crossover_rad_s, phase_margin_deg);
  const double gain = result.design.gain;
  const double order = result.design.order;
  result.margins = ComputeMargins([&](double w) {
    return gain * std::polar(std::pow(w, -order), -order * kPi / 2) * plant(w);
  });
  return result;
}

namespace {
constexpr char kDerivativeNoise[] = "derivative noise";
void RequireFiniteNonNegative(const char* field, double value) {
  if (!std::isfinite(value) || value < 0) {
    ThrowOption(kDerivativeNoise, field, "finite and >= 0", FormatDouble(value));
  }
}
}  // namespace

double DerivativeNoiseRms_V(double kd, double filter_s, double sample_period_s, double noise_mm) {
  RequireFiniteNonNegative("kd", kd);
  RequireFiniteNonNegative("derivative_filter_s", filter_s);
  RequireFinitePositive(kDerivativeNoise, "sample_period_s", sample_period_s);
  RequireFiniteNonNegative("noise_mm", noise_mm);
  const double t = sample_period_s;
  return kd * noise_mm * std::sqrt(2.0 / ((filter_s + t) * (2.0 * filter_s + t)));
}

double DerivativeFilterForNoise_s(double kd, double sample_period_s, double noise_mm,
                                  double bound_V) {
  RequireFiniteNonNegative("kd", kd);
  RequireFinitePositive(kDerivativeNoise, "sample_period_s", sample_period_s);
  RequireFiniteNonNegative("noise_mm", noise_mm);
  RequireFinitePositive(kDerivativeNoise, "bound_V", bound_V);
  const double t = sample_period_s;
  const double r = kd * noise_mm / bound_V;
  if (r <= t / std::sqrt(2.0)) return 0.0;
  return (std::sqrt(t * t + 16.0 * r * r) - 3.0 * t) / 4.0;
}

PidLoopDesign DesignPidLoop(const IpmcLinkParams& params, const FrequencyFunction& plant,
                            const PidTuningOptions& tuning) {
  using Complex = std::complex<double>;
  const StateSpace accurate = AccurateLinkPlant(params);
  PidLoopDesign result;
  result.paper_cost = PidStepCost(accurate, tuning)(PidGains{});
  result.tuned = TunePid(accurate, tuning);
  const PidGains g = result.tuned.gains;
  result.margins = ComputeMargins([&](double w) {
    const Complex s(0, w);
    return (g.kp + g.ki / s + g.kd * s / (tuning.derivative_filter_s * s + 1.0)) * plant(w);
  });
  return result;
}

}  // namespace ipmc
