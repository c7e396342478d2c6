// Sampled fractional-order integrator (paper eq. 13; eq. 14 gives
// K = 15.62, lambda = 0.62 for the IPMC link of eq. 7):
//
//   C_I(s) = K / s^lambda,   0 < lambda <= 1        [V per mm of error]
//
// realised as a continuous state-space block (a, b, c, d) in one of two
// ways (Config::realisation):
//  - kOustaloup (default): the Oustaloup approximation of s^-lambda
//    (sim/linear/oustaloup.h) with N pairs on the band [w_b, w_h],
//    scaled by K; the defaults are eq. 15's setting (N = 4 pairs on
//    [1e-3, 1e2] rad/s). Inside the band C_I(j w) is matched within the
//    Oustaloup ripple and outside it the gain levels off (finite DC gain:
//    no true integrator unless lambda = 1).
//  - kEq15: the paper's printed eq. 15 itself (controllers/paper_eq15.h),
//    the filter behind Table 5's C_I column; gain, order, N and the band
//    do not enter it (EvaluateExact still uses gain and order).
//
// Discretisation: exact zero-order hold (ZOH) at the sample period T
// (default 1 ms): the error e_k sampled at t_k is held over the sample, so
//   x_(k+1) = Ad x_k + Bd e_k,  u_k = c x_k + d e_k,
// with [Ad Bd; 0 1] = exp([a b; 0 0] T) (Eigen's matrix exponential, Pade
// with scaling and squaring). The discrete states equal the continuous
// block's states at the sample instants for a piecewise-constant error.
// Output clamp +-V_max (default 6 V, may be disabled) with anti-windup by
// conditional integration: when the unclamped output exceeds the limit and
// the error has the sign of the output (the block has positive gain, so it
// would drive the output further into saturation), the state is held.
#ifndef IPMC_SWIM_CONTROLLERS_FRACTIONAL_INTEGRATOR_H_
#define IPMC_SWIM_CONTROLLERS_FRACTIONAL_INTEGRATOR_H_

#include <complex>
#include <optional>
#include <string>

#include <Eigen/Dense>

#include "sim/linear/oustaloup.h"
#include "sim/linear/state_space.h"

namespace ipmc {

// The most Oustaloup pole-zero pairs a realisation may have.
constexpr int kMaxOustaloupPairs = 64;

// How the fractional integrator's s^-lambda is realised (see above).
enum class FractionalRealisation { kOustaloup, kEq15 };

// "oustaloup" / "eq15"; ParseFractionalRealisation returns nullopt for any
// other word.
const char* FractionalRealisationName(FractionalRealisation realisation);
std::optional<FractionalRealisation> ParseFractionalRealisation(const std::string& word);

// Discrete-time SISO state space, x_(k+1) = a x_k + b u_k,
// y_k = c x_k + d u_k, at a fixed sample period.
struct DiscreteStateSpace {
  Eigen::MatrixXd a;  // n x n
  Eigen::MatrixXd b;  // n x 1
  Eigen::MatrixXd c;  // 1 x n
  Eigen::MatrixXd d;  // 1 x 1
  double sample_period_s = 0.0;
};

// Exact zero-order-hold discretisation of `continuous` at `sample_period_s`
// via the matrix exponential of the augmented matrix [a b; 0 0] T. Throws
// std::invalid_argument for an invalid system or a sample period that is
// not finite and > 0.
DiscreteStateSpace DiscretizeZeroOrderHold(const StateSpace& continuous,
                                           double sample_period_s);

class FractionalIntegrator {
 public:
  struct Config {
    double gain = 15.62;        // K [V/(mm s^lambda)], finite and >= 0
    double order = 0.62;        // lambda, in (0, 1]
    int oustaloup_n = 4;        // N, in [1, kMaxOustaloupPairs]
    double w_low_rad_s = 1e-3;  // w_b, finite and > 0
    double w_high_rad_s = 1e2;  // w_h, finite and > w_b
    OustaloupVariant variant = OustaloupVariant::kNPairs;
    FractionalRealisation realisation = FractionalRealisation::kOustaloup;
    double sample_period_s = 1e-3;  // T [s], finite and > 0
    bool clamp_enabled = true;
    double v_max = 6.0;  // output limit [V], > 0 (checked if clamp_enabled)

    // Throws FieldError (sim/base/error.h, a std::invalid_argument) with a
    // one-line message naming the field and its allowed range (both also
    // carried as its field() and allowed()).
    void Validate() const;
  };

  // Validates `config`, builds and discretises the realisation, and starts
  // at rest. Throws std::invalid_argument for a bad configuration.
  explicit FractionalIntegrator(const Config& config);

  // One sample: error e_k = reference - measurement at t_k in, voltage u_k
  // (held until the next sample) out. Throws std::invalid_argument if
  // `error` is not finite.
  double Update(double error);

  // Back to rest (zero state).
  void Reset();

  // K s^-lambda on the principal branch (the ideal controller).
  std::complex<double> EvaluateExact(std::complex<double> s) const;
  // The continuous realisation c (s I - a)^-1 b + d (Oustaloup or eq. 15).
  std::complex<double> Evaluate(std::complex<double> s) const;

  const Config& config() const { return config_; }
  double sample_period_s() const { return config_.sample_period_s; }
  const StateSpace& continuous() const { return continuous_; }
  const DiscreteStateSpace& discrete() const { return discrete_; }
  const Eigen::VectorXd& state() const { return state_; }
  double last_output() const { return last_output_; }

 private:
  Config config_;
  StateSpace continuous_;
  DiscreteStateSpace discrete_;
  Eigen::VectorXd state_;
  double last_output_ = 0.0;
};

}  // namespace ipmc

#endif  // IPMC_SWIM_CONTROLLERS_FRACTIONAL_INTEGRATOR_H_
