// Oustaloup recursive approximation of the fractional operator s^gamma.
//
// Inside the band [w_b, w_h] the operator s^gamma (gain slope 20 gamma
// dB/dec, constant phase 90 gamma deg) is approximated by a ratio of
// first-order factors whose corner frequencies are spread geometrically
// over the band (A. Oustaloup, F. Levron, B. Mathieu, F. M. Nanot,
// "Frequency-band complex noninteger differentiator: characterization and
// synthesis", IEEE Trans. Circuits Syst. I 47(1), 2000, pp. 25-39).
//
// Two placements of the corners are provided:
//  - kNPairs: N zero/pole pairs, w_u = sqrt(w_h / w_b),
//      z_k = w_b w_u^((2k - 1 - gamma) / N),
//      p_k = w_b w_u^((2k - 1 + gamma) / N),   k = 1..N,
//    gain w_h^gamma. This is the form of the paper's eq. 15 (N = 4 pairs on
//    [1e-3, 1e2] rad/s; the printed coefficients correspond to
//    gamma = -0.6248 with this gain).
//  - k2NPlus1: the classic 2N + 1 pairs, k = -N..N,
//      z_k = w_b (w_h / w_b)^((k + N + (1 - gamma) / 2) / (2N + 1)),
//      p_k = w_b (w_h / w_b)^((k + N + (1 + gamma) / 2) / (2N + 1)),
//    gain w_h^gamma.
// In both forms the corners are symmetric about w_c = sqrt(w_b w_h)
// (p_(N+1-k) z_k = w_c^2), so the gain w_h^gamma gives exactly
// |H(j w_c)| = w_c^gamma and arg H(j w_c) = 90 gamma deg, and H tends to
// w_h^gamma (the ideal gain at w_h) as s -> infinity.
//
// Orders with |gamma| >= 1 are split as gamma = m + f with m = round(gamma)
// (ties away from zero) and f = gamma - m in [-0.5, 0.5]: the Oustaloup
// block approximates only s^f, whose corners stay close together, and s^m
// is exact (m integrators for m < 0). |gamma| < 1 is approximated directly
// (m = 0), as in the paper's eq. 15.
#ifndef IPMC_SWIM_CONTROLLERS_OUSTALOUP_H_
#define IPMC_SWIM_CONTROLLERS_OUSTALOUP_H_

#include <complex>
#include <vector>

#include "sim/linear/state_space.h"

namespace ipmc {

enum class OustaloupVariant { kNPairs, k2NPlus1 };

struct OustaloupConfig {
  double order = -0.5;        // gamma, any finite real with |gamma| <= 20
  double w_low_rad_s = 1e-3;  // w_b, band [w_b, w_h]
  double w_high_rad_s = 1e3;  // w_h
  int n = 4;  // zero/pole pairs (kNPairs) or N of the 2N+1 variant, >= 1
  OustaloupVariant variant = OustaloupVariant::kNPairs;

  // Throws std::invalid_argument with a one-line message naming the field
  // and its allowed range.
  void Validate() const;
};

// H(s) = gain * prod(s + z_k) / prod(s + p_k) * s^integer_order.
struct ZeroPoleGain {
  std::vector<double> zero_corners_rad_s;  // z_k > 0 (zero at s = -z_k)
  std::vector<double> pole_corners_rad_s;  // p_k > 0 (pole at s = -p_k)
  double gain = 1.0;
  int integer_order = 0;

  std::complex<double> Evaluate(std::complex<double> s) const;
};

// Integer part m and fractional part f of gamma = m + f (see above).
int OustaloupIntegerOrder(double order);
double OustaloupFractionalOrder(double order);

// Zeros, poles and gain of the approximation of s^config.order. The
// fractional part is approximated; integer_order = OustaloupIntegerOrder.
ZeroPoleGain OustaloupZpk(const OustaloupConfig& config);

// State-space realisation of a zero-pole-gain form with as many zero as
// pole corners: the gain followed by a cascade of first-order sections
// (s + z_k) / (s + p_k), each one state scaled so that its DC gain from
// input to state is 1,
//   x' = -p x + p u,  y = ((z - p) / p) x + u,
// then |m| integrators for m = integer_order < 0. Throws
// std::invalid_argument if the counts differ, a corner is not finite and
// > 0, or integer_order > 0 (an improper differentiator).
StateSpace ZeroPoleGainStateSpace(const ZeroPoleGain& zpk);

// ZeroPoleGainStateSpace(OustaloupZpk(config)). Throws
// std::invalid_argument if the realisation would be improper (m > 0, i.e.
// a differentiator); realise s^alpha with alpha >= 1 in a denominator by
// feedback instead (see sim/linear/ipmc_link_model.h).
StateSpace OustaloupStateSpace(const OustaloupConfig& config);

}  // namespace ipmc

#endif  // IPMC_SWIM_CONTROLLERS_OUSTALOUP_H_
