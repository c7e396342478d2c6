#include "sim/identify/controller_design.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "sim/io/numbers.h"
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

constexpr int kAccuratePairs = 20;
constexpr double kAccurateBandLow_rad_s = 1e-5;
constexpr double kAccurateBandHigh_rad_s = 1e5;

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

  NelderMeadResult result;
  const auto evaluate = [&](const Eigen::VectorXd& x) {
    ++result.evaluations;
    return FiniteOr(f(x));
  };
  // Vertices and their values, kept sorted by value (best first).
  std::vector<Eigen::VectorXd> vertex(n + 1, start);
  std::vector<double> value(n + 1);
  value[0] = evaluate(start);
  if (!std::isfinite(value[0])) Throw(where, "f is not finite at the start");
  for (int i = 0; i < n; ++i) {
    vertex[i + 1](i) += options.initial_step;
    value[i + 1] = evaluate(vertex[i + 1]);
  }
  std::vector<int> order(n + 1);
  const auto sort = [&]() {
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](int i, int j) { return value[i] < value[j]; });
    std::vector<Eigen::VectorXd> sorted_vertex(n + 1);
    std::vector<double> sorted_value(n + 1);
    for (int i = 0; i <= n; ++i) {
      sorted_vertex[i] = vertex[order[i]];
      sorted_value[i] = value[order[i]];
    }
    vertex.swap(sorted_vertex);
    value.swap(sorted_value);
  };
  sort();

  while (true) {
    double spread_x = 0.0, spread_f = 0.0;
    for (int i = 1; i <= n; ++i) {
      spread_x = std::max(spread_x, (vertex[i] - vertex[0]).cwiseAbs().maxCoeff());
      spread_f = std::max(spread_f, std::abs(value[i] - value[0]));
    }
    if (spread_x <= options.x_tolerance && spread_f <= options.f_tolerance) {
      result.converged = true;
      break;
    }
    if (result.evaluations >= options.max_evaluations) break;
    ++result.iterations;

    Eigen::VectorXd centroid = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < n; ++i) centroid += vertex[i];
    centroid /= n;
    const Eigen::VectorXd& worst = vertex[n];

    const Eigen::VectorXd reflected = centroid + (centroid - worst);
    const double f_reflected = evaluate(reflected);
    bool shrink = false;
    if (f_reflected < value[0]) {
      const Eigen::VectorXd expanded = centroid + 2.0 * (centroid - worst);
      const double f_expanded = evaluate(expanded);
      if (f_expanded < f_reflected) {
        vertex[n] = expanded;
        value[n] = f_expanded;
      } else {
        vertex[n] = reflected;
        value[n] = f_reflected;
      }
    } else if (f_reflected < value[n - 1]) {
      vertex[n] = reflected;
      value[n] = f_reflected;
    } else if (f_reflected < value[n]) {
      // Outside contraction.
      const Eigen::VectorXd contracted = centroid + 0.5 * (reflected - centroid);
      const double f_contracted = evaluate(contracted);
      if (f_contracted <= f_reflected) {
        vertex[n] = contracted;
        value[n] = f_contracted;
      } else {
        shrink = true;
      }
    } else {
      // Inside contraction.
      const Eigen::VectorXd contracted = centroid + 0.5 * (worst - centroid);
      const double f_contracted = evaluate(contracted);
      if (f_contracted < value[n]) {
        vertex[n] = contracted;
        value[n] = f_contracted;
      } else {
        shrink = true;
      }
    }
    if (shrink) {
      for (int i = 1; i <= n; ++i) {
        vertex[i] = vertex[0] + 0.5 * (vertex[i] - vertex[0]);
        value[i] = evaluate(vertex[i]);
      }
    }
    sort();
  }
  result.x = vertex[0];
  result.value = value[0];
  return result;
}

// ---------------------------------------------------------- PID tuning ---

std::vector<PidGains> DefaultPidStarts() {
  return {{8.12, 53.36, 0.61}, {1.0, 10.0, 0.1}, {20.0, 200.0, 2.0}, {2.0, 100.0, 1.0},
          {30.0, 20.0, 0.05}};
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
  const DiscreteStateSpace hold = DiscretizeZeroOrderHold(plant, options.sample_period_s);
  a_ = hold.a;
  b_ = hold.b.col(0);
  c_ = hold.c.row(0);
  d_ = hold.d(0, 0);
  sample_period_s_ = options.sample_period_s;
  samples_ = static_cast<int>(std::lround(options.horizon_s / options.sample_period_s));
  const ReferenceModel model(options.reference);
  reference_.resize(samples_ + 1);
  weight_.resize(samples_ + 1);
  for (int k = 0; k <= samples_; ++k) {
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
  config.clamp_enabled = false;
  PidController pid(config);

  const int n = static_cast<int>(a_.rows());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd next(n);
  double u = 0.0;
  double cost = 0.0;
  const auto output = [&]() { return (n > 0 ? c_.dot(x) : 0.0) + d_ * u; };
  for (int k = 0; k < samples_; ++k) {
    const double measured = output();  // y(t_k^-), before the new voltage
    if (!std::isfinite(measured) || std::abs(measured) > kDivergedOutput) return kInfinity;
    u = pid.Update(1.0 - measured);
    cost += weight_[k] * std::abs(reference_[k] - output());
    if (n > 0) {
      next.noalias() = a_ * x;
      next += b_ * u;
      x.swap(next);
    }
  }
  const double last = output();
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
        [&cost](const Eigen::VectorXd& x) { return cost(GainsFromLog(x)); }, LogGains(start),
        options.search);
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
  params.integrator.n = kAccuratePairs;
  return LinkStateSpace(params);
}

}  // namespace ipmc
