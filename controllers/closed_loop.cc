#include "sim/base/numbers.h"
#include "controllers/closed_loop.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace ipmc {
namespace {

constexpr int kMaxOutputSubsteps = 10000;
// Relative slack when comparing a horizon with a whole number of samples.
constexpr double kHorizonSlack = 1e-9;

void CheckSeries(const char* function, const std::vector<double>& time_s,
                 const std::vector<double>& output) {
  if (time_s.empty() || time_s.size() != output.size()) {
    throw std::invalid_argument(
        std::string(function) +
        ": time_s and output must be non-empty and of equal length, got " +
        std::to_string(time_s.size()) + " and " +
        std::to_string(output.size()));
  }
  for (std::size_t i = 0; i < time_s.size(); ++i) {
    if (!std::isfinite(time_s[i]) || !std::isfinite(output[i]) ||
        (i > 0 && !(time_s[i] > time_s[i - 1]))) {
      throw std::invalid_argument(
          std::string(function) +
          ": time_s must be finite and increasing and output finite; "
          "failed at index " +
          std::to_string(i));
    }
  }
}

// Samples of period T that cover `horizon_s`: the nearest whole number if
// horizon / T is one to within kHorizonSlack, else the next above.
long long WholeSamples(double horizon_s, double sample_period_s) {
  const double samples_real = horizon_s / sample_period_s;
  const double nearest = std::round(samples_real);
  return static_cast<long long>(
      std::abs(samples_real - nearest) <= kHorizonSlack * nearest
          ? nearest
          : std::ceil(samples_real));
}

// Time at which the straight line through (t0, y0) and (t1, y1) reaches
// `level` (y0 and y1 on either side of it, or one equal to it).
double CrossingTime(double t0, double y0, double t1, double y1, double level) {
  if (y1 == y0) return t1;
  return t0 + (t1 - t0) * (level - y0) / (y1 - y0);
}

}  // namespace

HeldPlant::HeldPlant(const StateSpace& plant, double hold_s)
    : HeldPlant(DiscretizeZeroOrderHold(plant, hold_s)) {}

HeldPlant::HeldPlant(DiscreteStateSpace hold)
    : hold_(std::move(hold)),
      x_(Eigen::VectorXd::Zero(hold_.a.rows())),
      next_(hold_.a.rows()) {}

double HeldPlant::Output() const {
  return (x_.size() > 0 ? (hold_.c * x_)(0, 0) : 0.0) + hold_.d(0, 0) * held_input_V_;
}

void HeldPlant::Advance() {
  if (x_.size() == 0) return;
  next_.noalias() = hold_.a * x_;
  next_ += hold_.b.col(0) * held_input_V_;
  x_.swap(next_);
}

void StepSimulation::Validate() const {
  if (!std::isfinite(horizon_s) || !(horizon_s > 0)) {
    throw std::invalid_argument(
        "StepSimulation.horizon_s must be finite and > 0, got " +
        FormatDouble(horizon_s));
  }
  if (!std::isfinite(step_amplitude) || step_amplitude == 0) {
    throw std::invalid_argument(
        "StepSimulation.step_amplitude must be finite and != 0, got " +
        FormatDouble(step_amplitude));
  }
  if (output_substeps < 1 || output_substeps > kMaxOutputSubsteps) {
    throw std::invalid_argument(
        "StepSimulation.output_substeps must be in [1, " +
        std::to_string(kMaxOutputSubsteps) + "], got " +
        std::to_string(output_substeps));
  }
  if (!std::isfinite(max_horizon_s) || max_horizon_s < 0) {
    throw std::invalid_argument(
        "StepSimulation.max_horizon_s must be finite and >= 0, got " +
        FormatDouble(max_horizon_s));
  }
  if (!(settling_band > 0) || !(settling_band < 1)) {
    throw std::invalid_argument(
        "StepSimulation.settling_band must be in (0, 1), got " +
        FormatDouble(settling_band));
  }
}

ClosedLoopResponse SimulateClosedLoopStep(const StateSpace& plant,
                                          const ControllerUpdate& controller,
                                          double sample_period_s,
                                          const StepSimulation& simulation) {
  simulation.Validate();
  plant.Validate("SimulateClosedLoopStep: plant");
  if (!std::isfinite(sample_period_s) || !(sample_period_s > 0)) {
    throw std::invalid_argument(
        "SimulateClosedLoopStep: sample_period_s must be finite and > 0, "
        "got " +
        FormatDouble(sample_period_s));
  }
  if (!controller) {
    throw std::invalid_argument("SimulateClosedLoopStep: controller is empty");
  }
  const long long samples = WholeSamples(simulation.horizon_s, sample_period_s);
  const long long max_samples =
      WholeSamples(std::max(simulation.max_horizon_s, simulation.horizon_s),
                   sample_period_s);
  const int substeps = simulation.output_substeps;
  const double substep_s = sample_period_s / substeps;
  HeldPlant held(plant, substep_s);

  ClosedLoopResponse response;
  response.step_amplitude = simulation.step_amplitude;
  response.sample_period_s = sample_period_s;
  const std::size_t points = static_cast<std::size_t>(samples) * substeps + 1;
  response.time_s.reserve(points);
  response.output.reserve(points);
  response.control.reserve(points);

  double u = 0.0;
  long long k = 0;
  // Samples k up to `end` (exclusive), recording [t_k, t_(k+1)).
  const auto advance_to = [&](long long end) {
    for (; k < end; ++k) {
      const double measured = held.Output();  // y(t_k^-)
      u = controller(simulation.step_amplitude - measured);
      if (!std::isfinite(u)) {
        throw std::runtime_error(
            "SimulateClosedLoopStep: controller output is not finite at t = " +
            FormatDouble(k * sample_period_s) + " s");
      }
      held.Hold(u);
      for (int j = 0; j < substeps; ++j) {
        response.time_s.push_back(static_cast<double>(k * substeps + j) *
                                  substep_s);
        response.output.push_back(held.Output());
        response.control.push_back(u);
        held.Advance();
      }
    }
  };
  advance_to(samples);
  // The extension, a horizon at a time, while the metrics are open.
  while (k < max_samples &&
         CheckStepRecord(response, simulation.settling_band) !=
             StepRecordStatus::kDetermined) {
    advance_to(std::min(max_samples, k + samples));
  }
  response.time_s.push_back(static_cast<double>(k * substeps) * substep_s);
  response.output.push_back(held.Output());
  response.control.push_back(u);
  return response;
}

ClosedLoopResponse SimulateClosedLoopStep(const StateSpace& plant,
                                          PidController& controller,
                                          const StepSimulation& simulation) {
  controller.Reset();
  return SimulateClosedLoopStep(
      plant, [&controller](double error) { return controller.Update(error); },
      controller.sample_period_s(), simulation);
}

ClosedLoopResponse SimulateClosedLoopStep(const StateSpace& plant,
                                          FractionalIntegrator& controller,
                                          const StepSimulation& simulation) {
  controller.Reset();
  return SimulateClosedLoopStep(
      plant, [&controller](double error) { return controller.Update(error); },
      controller.sample_period_s(), simulation);
}

StepMetrics ComputeStepMetrics(const std::vector<double>& time_s,
                               const std::vector<double>& output,
                               double final_value, double settling_band) {
  CheckSeries("ComputeStepMetrics", time_s, output);
  if (!std::isfinite(final_value) || final_value == 0) {
    throw std::invalid_argument(
        "ComputeStepMetrics: final_value must be finite and != 0, got " +
        FormatDouble(final_value));
  }
  if (!(settling_band > 0) || !(settling_band < 1)) {
    throw std::invalid_argument(
        "ComputeStepMetrics: settling_band must be in (0, 1), got " +
        FormatDouble(settling_band));
  }
  const std::size_t n = time_s.size();
  // Work with the normalised response r = y / final (rises towards 1).
  std::vector<double> r(n);
  for (std::size_t i = 0; i < n; ++i) r[i] = output[i] / final_value;

  StepMetrics metrics;
  metrics.final_value = final_value;

  const std::size_t i_peak = static_cast<std::size_t>(
      std::max_element(r.begin(), r.end()) - r.begin());
  double peak_r = r[i_peak];
  double peak_t = time_s[i_peak];
  if (i_peak > 0 && i_peak + 1 < n) {
    // Vertex of the parabola through the three points around the maximum.
    const double t0 = time_s[i_peak - 1], t1 = time_s[i_peak],
                 t2 = time_s[i_peak + 1];
    const double y0 = r[i_peak - 1], y1 = r[i_peak], y2 = r[i_peak + 1];
    const double d01 = (y1 - y0) / (t1 - t0);
    const double d12 = (y2 - y1) / (t2 - t1);
    // Newton form y = y0 + d01 (t - t0) + c (t - t0)(t - t1).
    const double c = (d12 - d01) / (t2 - t0);
    if (c < 0) {
      const double vertex = 0.5 * (t0 + t1) - d01 / (2 * c);
      if (vertex > t0 && vertex < t2) {
        peak_t = vertex;
        peak_r = y0 + d01 * (vertex - t0) + c * (vertex - t0) * (vertex - t1);
      }
    }
  }
  metrics.peak_value = peak_r * final_value;
  metrics.peak_time_s = peak_t;
  metrics.overshoot_percent = std::max(0.0, 100.0 * (peak_r - 1.0));

  std::optional<double> t10;
  std::optional<double> t90;
  for (std::size_t i = 0; i < n && !t90; ++i) {
    if (!t10 && r[i] >= 0.1) {
      t10 = i == 0
                ? time_s[0]
                : CrossingTime(time_s[i - 1], r[i - 1], time_s[i], r[i], 0.1);
    }
    if (r[i] >= 0.9) {
      t90 = i == 0
                ? time_s[0]
                : CrossingTime(time_s[i - 1], r[i - 1], time_s[i], r[i], 0.9);
    }
  }
  if (t10 && t90) metrics.rise_time_s = *t90 - *t10;

  std::size_t last_outside = n;
  for (std::size_t i = n; i-- > 0;) {
    if (std::abs(r[i] - 1.0) > settling_band) {
      last_outside = i;
      break;
    }
  }
  if (last_outside == n) {
    metrics.settling_time_s = time_s[0];
  } else if (last_outside + 1 < n) {
    const double level =
        r[last_outside] > 1.0 ? 1.0 + settling_band : 1.0 - settling_band;
    metrics.settling_time_s =
        CrossingTime(time_s[last_outside], r[last_outside],
                     time_s[last_outside + 1], r[last_outside + 1], level);
  }
  return metrics;
}

StepMetrics ComputeStepMetrics(const ClosedLoopResponse& response,
                               double settling_band) {
  return ComputeStepMetrics(response.time_s, response.output,
                            response.step_amplitude, settling_band);
}

StepRecordStatus CheckStepRecord(const ClosedLoopResponse& response,
                                 double settling_band) {
  const StepMetrics metrics = ComputeStepMetrics(response, settling_band);
  const double t_end = response.time_s.back();
  const double last_interval_s =
      response.time_s.size() > 1
          ? t_end - response.time_s[response.time_s.size() - 2]
          : 0.0;
  if (metrics.peak_time_s >= t_end - last_interval_s) {
    return StepRecordStatus::kPeakAtEnd;
  }
  if (!metrics.rise_time_s) return StepRecordStatus::kBelow90Percent;
  if (!metrics.settling_time_s) return StepRecordStatus::kOutsideBand;
  // In the band for at least as long as it took to enter it for good.
  if (*metrics.settling_time_s > 0.5 * (t_end - response.time_s.front())) {
    return StepRecordStatus::kSettledLate;
  }
  return StepRecordStatus::kDetermined;
}

const char* StepRecordStatusText(StepRecordStatus status) {
  switch (status) {
    case StepRecordStatus::kDetermined:
      return "determined";
    case StepRecordStatus::kBelow90Percent:
      return "below 90 %";
    case StepRecordStatus::kPeakAtEnd:
      return "peak at the end (still rising)";
    case StepRecordStatus::kOutsideBand:
      return "outside the settling band at the end";
    case StepRecordStatus::kSettledLate:
      return "settled after half the record";
  }
  return "unknown";
}

double ReferenceModelCost(const std::vector<double>& time_s,
                          const std::vector<double>& output,
                          const ReferenceModel& model, double step_amplitude,
                          double horizon_s) {
  CheckSeries("ReferenceModelCost", time_s, output);
  if (!std::isfinite(step_amplitude)) {
    throw std::invalid_argument(
        "ReferenceModelCost: step_amplitude must be finite, got " +
        FormatDouble(step_amplitude));
  }
  if (time_s.front() != 0.0) {
    throw std::invalid_argument(
        "ReferenceModelCost: time_s must start at 0, got " +
        FormatDouble(time_s.front()));
  }
  const double t_end = time_s.back();
  if (!std::isfinite(horizon_s) || !(horizon_s > 0) ||
      horizon_s > t_end * (1 + kHorizonSlack)) {
    throw std::invalid_argument(
        "ReferenceModelCost: horizon_s must be in (0, " + FormatDouble(t_end) +
        "], got " + FormatDouble(horizon_s));
  }
  const auto weighted_error = [&](double t, double y) {
    return (0.5 + 0.5 * t) *
           std::abs(step_amplitude * model.StepResponse(t) - y);
  };
  double cost = 0;
  double previous = weighted_error(time_s[0], output[0]);
  for (std::size_t i = 1; i < time_s.size(); ++i) {
    const double t0 = time_s[i - 1];
    double t1 = time_s[i];
    double y1 = output[i];
    const bool last = t1 >= horizon_s;
    if (last && t1 > horizon_s) {
      y1 = output[i - 1] +
           (output[i] - output[i - 1]) * (horizon_s - t0) / (t1 - t0);
      t1 = horizon_s;
    }
    const double current = weighted_error(t1, y1);
    cost += 0.5 * (t1 - t0) * (previous + current);
    previous = current;
    if (last) break;
  }
  return cost;
}

double ReferenceModelCost(const ClosedLoopResponse& response,
                          const ReferenceModel& model, double horizon_s) {
  return ReferenceModelCost(response.time_s, response.output, model,
                            response.step_amplitude, horizon_s);
}

}  // namespace ipmc
