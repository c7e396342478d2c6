// Sampled PID controller in parallel form (paper eq. 10; eq. 12 gives the
// tuned gains Kp = 8.12, Ki = 53.36, Kd = 0.61 for the IPMC link of eq. 7):
//
//   C(s) = Kp + Ki / s + Kd s / (Tf s + 1)        [V per mm of error]
//
// Tf = 0 is the ideal derivative Kd s of the paper; Tf > 0 adds a
// first-order derivative filter (in the textbook "N" form, Tf = Kd / (Kp N);
// see DerivativeFilterTimeFromN).
//
// Discretisation at the fixed sample period T (default 1 ms, the 1 kHz of
// the data-acquisition board), with e_k the error sampled at t_k = k T and
// u_k held over [t_k, t_(k+1)) (zero-order hold):
//  - integral: backward Euler, I_k = I_(k-1) + Ki T e_k;
//  - derivative: filtered, backward difference,
//      D_k = Tf / (Tf + T) D_(k-1) + Kd / (Tf + T) (e_k - e_(k-1)),
//    which for Tf = 0 is Kd (e_k - e_(k-1)) / T. After Reset() the previous
//    error is 0 (the loop was at rest), so a step of the error gives the
//    discrete counterpart of the continuous derivative impulse: one sample
//    of Kd e / T (area Kd e), as the linear continuous loop would see;
//  - u_k = Kp e_k + I_k + D_k, then clamped to [-V_max, V_max] if enabled.
// Anti-windup: conditional integration (clamping). When the new error
// would drive the unclamped output past the limit, the integral advances
// only until the output reaches the limit, and holds its previous value if
// the output is already at or beyond the limit without the increment; it
// always moves freely back out of saturation.
// With the clamp disabled the controller is linear (the paper's Simulink
// setting).
#ifndef IPMC_SWIM_CONTROLLERS_PID_H_
#define IPMC_SWIM_CONTROLLERS_PID_H_

#include <complex>

namespace ipmc {

class PidController {
 public:
  struct Config {
    double kp = 8.12;   // proportional gain [V/mm], >= 0
    double ki = 53.36;  // integral gain [V/(mm s)], >= 0
    double kd = 0.61;   // derivative gain [V s/mm], >= 0
    // Derivative filter time constant Tf [s], >= 0 (0: no filter).
    double derivative_filter_time_s = 0.0;
    double sample_period_s = 1e-3;  // T [s], > 0
    bool clamp_enabled = true;
    double v_max = 6.0;  // output limit [V], > 0 (checked if clamp_enabled)

    // Throws FieldError (sim/base/error.h, a std::invalid_argument) with a
    // one-line message naming the field and its allowed range (both also
    // carried as its field() and allowed()). All fields must be finite.
    void Validate() const;
  };

  // Validates `config` (throws std::invalid_argument) and starts at rest.
  explicit PidController(const Config& config);

  // One sample: takes the error e_k = reference - measurement at t_k and
  // returns the voltage u_k to hold until the next sample. Throws
  // std::invalid_argument if `error` is not finite.
  double Update(double error);

  // Back to rest: zero integral, derivative state and previous error.
  void Reset();

  // Continuous transfer function C(s) = Kp + Ki/s + Kd s/(Tf s + 1) (no
  // clamp, no sampling), e.g. for Bode plots: Evaluate({0, w}).
  std::complex<double> Evaluate(std::complex<double> s) const;

  const Config& config() const { return config_; }
  double sample_period_s() const { return config_.sample_period_s; }
  // The integral term I_k and the last output (after the clamp).
  double integral() const { return integral_; }
  double last_output() const { return last_output_; }

  // Tf = Kd / (Kp N) for a derivative gain limited to N times Kp at high
  // frequency. Throws std::invalid_argument unless kp > 0, kd >= 0, n > 0.
  static double DerivativeFilterTimeFromN(double kp, double kd, double n);

 private:
  Config config_;
  double integral_ = 0.0;
  double derivative_ = 0.0;
  double previous_error_ = 0.0;
  double last_output_ = 0.0;
};

}  // namespace ipmc

#endif  // IPMC_SWIM_CONTROLLERS_PID_H_
