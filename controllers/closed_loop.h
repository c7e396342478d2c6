// Sampled-data closed-loop step response of a linear plant under one of
// the sampled controllers, its step metrics, and the design cost of the
// paper's eq. 11.
//
// Loop (unity negative feedback, step reference r(t) = A for t >= 0):
//   at each sample t_k = k T the controller takes e_k = A - y(t_k^-) and
//   returns u_k, held over [t_k, t_(k+1)); the continuous plant
//   (a, b, c, d) is advanced exactly over the hold by its zero-order-hold
//   discretisation (matrix exponential), so the only approximation is the
//   controller's own discretisation. y(t_k^-) = c x(t_k) + d u_(k-1) is the
//   output just before the new voltage is applied (equal to y(t_k) for a
//   strictly proper plant, d = 0, such as s^-0.5 G1).
// The response is recorded `output_substeps` times per sample period (exact
// values of the continuous plant output between the samples), from t = 0 to
// t = N T with N = ceil(horizon / T). With max_horizon_s > horizon_s the
// record goes on, horizon_s at a time (the last span cut at
// max_horizon_s), until CheckStepRecord finds its step metrics determined.
//
// Eq. 11: J = int_0^H (1/2 + t/2) |y_r(t) - y(t)| dt, with y_r the
// reference model's step response (controllers/reference_model.h) scaled
// by A; computed by the trapezoidal rule on the recorded points.
#ifndef IPMC_SWIM_CONTROLLERS_CLOSED_LOOP_H_
#define IPMC_SWIM_CONTROLLERS_CLOSED_LOOP_H_

#include <cmath>
#include <functional>
#include <optional>
#include <vector>

#include "controllers/fractional_integrator.h"
#include "controllers/pid.h"
#include "controllers/reference_model.h"
#include "sim/linear/state_space.h"

namespace ipmc {

// A continuous SISO plant behind a zero-order hold, the one sampled loop
// of the program (the step responses here, the PID tuning's eq. 11 loop,
// Table 5's transfer-function loop): the input u is held over each
// interval, over which the state advances exactly by the plant's
// zero-order-hold discretisation (x <- a x + b u).
class HeldPlant {
 public:
  // Discretises `plant` over `hold_s`; throws std::invalid_argument for an
  // invalid plant or hold.
  HeldPlant(const StateSpace& plant, double hold_s);
  // From a discretisation made once (copied), for many loops.
  explicit HeldPlant(DiscreteStateSpace hold);

  // y = c x + d u with the input now held: before Hold(u_k), y(t_k^-).
  double Output() const;
  void Hold(double u) { held_input_V_ = u; }
  // x over one hold interval under the held input.
  void Advance();

 private:
  DiscreteStateSpace hold_;
  Eigen::VectorXd x_, next_;
  double held_input_V_ = 0.0;  // u_k, the voltage held over the interval [V]
};

// The tracking indices of an error e [mm] sampled every T [s] from t = 0,
// by the rectangle rule: IAE = sum |e_k| T [mm s], ITAE = sum t_k |e_k| T
// [mm s^2] (the `run` command's and Table 5's).
struct TrackingIndices {
  double iae_mm_s = 0.0;
  double itae_mm_s2 = 0.0;
  void Add(double t_s, double error_mm, double sample_period_s) {
    iae_mm_s += std::abs(error_mm) * sample_period_s;
    itae_mm_s2 += t_s * std::abs(error_mm) * sample_period_s;
  }
};

struct StepSimulation {
  double horizon_s = 10.0;      // finite and > 0
  double step_amplitude = 1.0;  // A, finite and != 0
  int output_substeps = 1;      // recorded points per sample, in [1, 10000]
  // Extension past horizon_s while the metrics are not determined, up to
  // this time [s]; finite and >= 0, no extension unless > horizon_s.
  double max_horizon_s = 0.0;
  double settling_band = 0.02;  // the extension's criterion, in (0, 1)

  // Throws std::invalid_argument naming the field and its allowed range.
  void Validate() const;
};

struct ClosedLoopResponse {
  // Parallel arrays, N * output_substeps + 1 points from t = 0.
  std::vector<double> time_s;
  std::vector<double> output;   // y(t) = c x(t) + d u(t)
  std::vector<double> control;  // u(t), the voltage held at t
  double step_amplitude = 1.0;
  double sample_period_s = 0.0;
};

// One controller sample: error in, held control out.
using ControllerUpdate = std::function<double(double error)>;

// Simulates the loop with a controller given as its update function and
// sample period (the caller resets it). Throws std::invalid_argument for an
// invalid plant, sample period or `simulation`.
ClosedLoopResponse SimulateClosedLoopStep(
    const StateSpace& plant, const ControllerUpdate& controller,
    double sample_period_s, const StepSimulation& simulation = {});

// Same with the controller Reset() first and its own sample period.
ClosedLoopResponse SimulateClosedLoopStep(
    const StateSpace& plant, PidController& controller,
    const StepSimulation& simulation = {});
ClosedLoopResponse SimulateClosedLoopStep(
    const StateSpace& plant, FractionalIntegrator& controller,
    const StepSimulation& simulation = {});

struct StepMetrics {
  double final_value = 0;  // the value the metrics refer to
  double peak_value = 0;   // maximum of y / final_value, times final_value
  double peak_time_s = 0;
  // 100 (peak - final) / final, or 0 if the response never exceeds final.
  double overshoot_percent = 0;
  // From the first 10 % crossing to the first 90 % crossing of final
  // (linear interpolation); empty if 90 % is never reached.
  std::optional<double> rise_time_s;
  // Time after which |y - final| stays within band * |final| (linear
  // interpolation of the last exit); empty if the response is outside the
  // band at the last point.
  std::optional<double> settling_time_s;
};

// Step metrics of a recorded response. The peak is refined by a parabola
// through the largest sample and its neighbours. Throws
// std::invalid_argument if the arrays are empty, differ in length or are
// not increasing in time, if final_value is 0 or not finite, or if
// settling_band is not in (0, 1).
StepMetrics ComputeStepMetrics(const std::vector<double>& time_s,
                               const std::vector<double>& output,
                               double final_value, double settling_band = 0.02);
StepMetrics ComputeStepMetrics(const ClosedLoopResponse& response,
                               double settling_band = 0.02);

// Whether a record holds its step metrics, or why not (the first that
// applies):
//  - kPeakAtEnd: its maximum is at the last sample, so the response may
//    still rise (overshoot and peak are lower bounds);
//  - kBelow90Percent: it turned without reaching 90 % of the final value
//    (no rise time);
//  - kOutsideBand: it ends outside the settling band (no settling time);
//  - kSettledLate: it entered the band for the last time after half the
//    record. The loops of a fractional plant approach their final value
//    along an algebraic tail, so a response that has stayed in the band
//    for less time than it took to get there is not taken as settled;
//  - kDetermined: none of these.
enum class StepRecordStatus {
  kDetermined,
  kPeakAtEnd,
  kBelow90Percent,
  kOutsideBand,
  kSettledLate
};
StepRecordStatus CheckStepRecord(const ClosedLoopResponse& response,
                                 double settling_band = 0.02);
// "determined", "below 90 %", "peak at the end (still rising)", "outside
// the settling band at the end", "settled after half the record".
const char* StepRecordStatusText(StepRecordStatus status);

// Eq. 11 over [0, horizon_s] (linear interpolation inside the last
// interval). Throws std::invalid_argument if the arrays are inconsistent,
// do not start at t = 0, or end before horizon_s.
double ReferenceModelCost(const std::vector<double>& time_s,
                          const std::vector<double>& output,
                          const ReferenceModel& model, double step_amplitude,
                          double horizon_s);
double ReferenceModelCost(const ClosedLoopResponse& response,
                          const ReferenceModel& model, double horizon_s);

}  // namespace ipmc

#endif  // IPMC_SWIM_CONTROLLERS_CLOSED_LOOP_H_
