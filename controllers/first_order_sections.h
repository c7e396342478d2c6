// A discrete SISO block with real, distinct poles as parallel first-order
// sections, the form a fixed-rate processor runs the fractional integrator
// in (docs/PROTOTYPE.md): its transfer function
//
//   H(z) = d + sum_i c_i b_i / (z - p_i),   p_i = 1 - alpha_i,
//
// taken from the block's (a, b, c, d) by its modal decomposition
// (a = V diag(p) V^-1: the residue of pole p_i is (c V)_i (V^-1 b)_i). Each
// section advances its own state,
//
//   x_i,(k+1) = x_i,k - alpha_i x_i,k + b_i e_k,   u_k = d e_k + sum_i c_i x_i,k,
//
// with b_i = alpha_i (unit DC gain: x_i is the error low-passed at the
// pole's corner, in the error's unit) where alpha_i > 0, and b_i = 1 for a
// pole at z = 1 (alpha_i = 0, a summing integrator). Keeping alpha_i = 1 -
// p_i rather than p_i keeps a slow pole's corner in a float's 24 bits: p =
// 0.9999877 rounds to float with a relative error of 2.4e-3 in 1 - p, alpha
// = 1.23e-5 with 6e-8. Real poles paired into second-order sections would
// put 1 - p_1 p_2 and p_1 + p_2 in the coefficients instead, which float
// rounding turns into other (or complex) poles.
#ifndef IPMC_SWIM_CONTROLLERS_FIRST_ORDER_SECTIONS_H_
#define IPMC_SWIM_CONTROLLERS_FIRST_ORDER_SECTIONS_H_

#include <complex>
#include <vector>

#include "controllers/fractional_integrator.h"

namespace ipmc {

struct FirstOrderSection {
  double alpha = 0;  // 1 - p, the pole's distance below z = 1
  double b = 0;      // input coefficient
  double c = 0;      // output coefficient
  double pole() const { return 1.0 - alpha; }
  // The section's continuous corner -ln(p) / T [rad/s] (0 for p = 1).
  double CornerRadS(double sample_period_s) const;
};

struct ParallelSections {
  double d = 0;  // direct term
  std::vector<FirstOrderSection> sections;  // slowest (smallest alpha) first
  double sample_period_s = 0;

  // H(z) = d + sum c_i b_i / (z - p_i).
  std::complex<double> Evaluate(std::complex<double> z) const;
};

// The sections of `block`. Throws std::invalid_argument unless its poles
// are real, distinct and in (-1, 1], or if the sections' H(z) departs from
// the block's c (z I - a)^-1 b + d by more than 1e-9 of its magnitude at
// any of 60 frequencies from 1e-6 to pi / T rad/s (a check of the
// decomposition's rounding).
ParallelSections ParallelFirstOrderSections(const DiscreteStateSpace& block);

}  // namespace ipmc

#endif  // IPMC_SWIM_CONTROLLERS_FIRST_ORDER_SECTIONS_H_
