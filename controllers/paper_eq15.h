// The paper's eq. 15: its printed four-pair Oustaloup approximation, on
// [1e-3, 1e2] rad/s, of the fractional integrator of eq. 14,
// C_I(s) = 15.62 / s^0.62:
//
//   C_I*(s) = (32.08 s^4 + 1981 s^3 + 6511 s^2 + 1196 s + 11.7)
//           / (36.47 s^4 + 372.9 s^3 + 202.9 s^2 + 6.175 s + 0.01)  [V/mm]
//
// This is the one definition of its coefficients; the bode command and
// the closed-loop fractional controller (controllers/
// fractional_integrator.h, realisation kEq15) read them from here. The
// printed coefficients carry four significant digits and are the
// N-pairs Oustaloup construction of order -0.6248 (0.04 %) rather than
// eq. 14's -0.62 (2.8 %; tests/oustaloup_test.cc).
//
// Realisation: both quartics have four real negative roots, the corners
// z_k and p_k (numerator and denominator), so
//   C_I*(s) = g prod_k (s + z_k) / (s + p_k),  g = 32.08 / 36.47,
// which is realised like the Oustaloup blocks, as a cascade of
// first-order sections (sim/linear/oustaloup.h, ZeroPoleGainStateSpace).
// The roots come from the eigenvalues of the polynomials' companion
// matrices, polished by Newton steps on the printed polynomials.
#ifndef IPMC_SWIM_CONTROLLERS_PAPER_EQ15_H_
#define IPMC_SWIM_CONTROLLERS_PAPER_EQ15_H_

#include <array>
#include <complex>
#include <string>

#include "sim/linear/oustaloup.h"
#include "sim/linear/state_space.h"

namespace ipmc {

// Eq. 15 as printed, highest power of s first.
inline constexpr std::array<double, 5> kEq15Numerator = {32.08, 1981.0, 6511.0, 1196.0, 11.7};
inline constexpr std::array<double, 5> kEq15Denominator = {36.47, 372.9, 202.9, 6.175, 0.01};

// The printed ratio of quartics at s (Horner's rule).
std::complex<double> Eq15Evaluate(std::complex<double> s);

// "C(s) = (32.08 s^4 + ... + 11.7) / (36.47 s^4 + ... + 0.01) (eq. 15)".
std::string Eq15Description();

// Corners (ascending) and gain of eq. 15 in the form
// g prod (s + z_k) / (s + p_k); zeros and poles are paired in ascending
// order. Throws std::logic_error if a root is not real and negative
// (impossible for the printed coefficients; a guard against editing them).
ZeroPoleGain Eq15ZeroPoleGain();

// The cascade realisation of Eq15ZeroPoleGain(): four states, one per
// first-order section.
StateSpace Eq15StateSpace();

}  // namespace ipmc

#endif  // IPMC_SWIM_CONTROLLERS_PAPER_EQ15_H_
