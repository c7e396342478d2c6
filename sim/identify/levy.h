// Identification of an IPMC link model from a measured frequency response
// by Levy's method (paper section 4.2; E. C. Levy, "Complex-curve fitting",
// IRE Trans. Automatic Control AC-4, 1959, pp. 37-44).
//
// The measured response P(j w) (e.g. from sim/identify/welch.h, [mm/V]) holds the
// fractional integrator H(s) = s^-0.5 of eq. 4 in series with the
// mechanical model G(s). The integrator is removed first:
//   G_meas(j w) = P(j w) / (j w)^h,  h = integrator_order = -0.5,
// i.e. P is multiplied by (j w)^0.5, with (j w)^g = w^g exp(j g pi / 2).
// Then, over the points w_k of the band [w_low, w_high] (default the
// paper's [0.2, 50] rad/s), G = N / D is fitted by Levy's linearised least
// squares: minimise
//   J = sum_k |G_meas(j w_k) D(j w_k) - N(j w_k)|^2,
// which is linear in the parameters (real and imaginary parts stacked,
// solved by column-pivoted Householder QR on scaled columns):
//   G1 (eq. 5): N = a0, D = b2 s^2 + b1 s + 1;
//   G2 (eq. 6): N = a0, D = b1 s^alpha + 1, for each alpha of the sweep
//     alpha = 1 + k delta, k = 1..(1/delta - 1) (delta = 0.01: 1.01..1.99),
//     keeping the stable fit of least J (the paper's procedure).
// Stability tests:
//   G1: b2 > 0 and b1 > 0 (Routh-Hurwitz for a quadratic; b2 = 0 with
//     b1 > 0 is a stable first-order lag and counts as stable too).
//   G2: 1/(b1 s^alpha + 1) is a commensurate-order system in lambda =
//     s^alpha with the single root lambda = -1/b1. Matignon's theorem:
//     stable iff |arg(lambda)| > alpha pi / 2. For b1 > 0, arg = pi >
//     alpha pi / 2 for every alpha < 2; for b1 < 0, arg = 0: unstable. So
//     for alpha in (1, 2) the test is b1 > 0.
//
// Fit indices (Table 3), all on the complex response with the integrator
// (the fitted P = (j w)^h G against the measured P, as the table compares
// "P1" and "P2"), over the K band points, with e_k = P(j w_k) - P_model(j w_k):
//   J    = Levy's criterion above (on G, integrator removed), [(mm/V)^2];
//   MSE  = (1/K) sum_k |e_k|^2                                [(mm/V)^2];
//   MAD  = (1/K) sum_k |e_k|                                  [mm/V];
//   MD   = max_k |e_k|                                        [mm/V];
//   R^2  = 1 - sum_k |e_k|^2 / sum_k |P(j w_k) - mean_k P(j w_k)|^2.
//
// Bad input throws std::invalid_argument with one line naming the field:
// mismatched lengths, non-finite values, frequencies not positive and
// strictly increasing, a band that is not 0 < w_low < w_high or reaches
// outside the measured frequencies [w_first, w_last], fewer than 3 points
// in the band.
#pragma once

#include <complex>
#include <vector>

#include "sim/linear/ipmc_link_model.h"
#include "sim/identify/welch.h"

namespace ipmc {

struct LevyOptions {
  double w_low_rad_s = 0.2;   // band [w_low, w_high], 0 < w_low < w_high
  double w_high_rad_s = 50.0;
  double integrator_order = -0.5;  // h, removed before fitting; |h| <= 2
  double alpha_step = 0.01;        // delta of G2's sweep, in [1e-4, 0.5]

  // Throws std::invalid_argument naming the field and its allowed range.
  void Validate() const;
};

struct FitIndices {
  double levy_cost = 0;      // J
  double mse = 0;            // MSE
  double mad = 0;            // MAD
  double max_deviation = 0;  // MD
  double r_squared = 0;      // R^2
  int points = 0;            // K
  double w_first_rad_s = 0;  // first and last band point used
  double w_last_rad_s = 0;
};

struct LinkModelFit {
  // kind, a0_mm_per_V, b1 and b2_s2 (G1) or b1 and alpha (G2);
  // integrator.order = the removed integrator's order. The other fields
  // keep IpmcLinkParams' defaults, so a stable fit can drive the
  // simulator (LinkStateSpace) or LinkResponseExact directly.
  IpmcLinkParams params;
  bool stable = false;
  FitIndices indices;
};

struct LinkIdentification {
  LinkModelFit g1;
  LinkModelFit g2;          // the stable G2 of least J (see stable)
  int g2_orders_tried = 0;  // alphas swept
  int g2_orders_stable = 0; // of which gave a stable fit
};

// The model's P(j w) = (j w)^h G(j w) for any parameters (no validation,
// unstable ones included).
std::complex<double> FittedResponse(const IpmcLinkParams& params, double w_rad_s);

// Levy's fit of G1; of G2 at a fixed alpha; of G2 with alpha swept over
// (1, 2) (the stable fit of least J; if no alpha gives a stable fit, the
// fit of least J, with stable = false).
LinkModelFit FitG1Levy(const std::vector<double>& w_rad_s,
                       const std::vector<std::complex<double>>& response,
                       const LevyOptions& options = {});
LinkModelFit FitG2LevyAtOrder(const std::vector<double>& w_rad_s,
                              const std::vector<std::complex<double>>& response, double alpha,
                              const LevyOptions& options = {});
LinkIdentification IdentifyLinkModels(const std::vector<double>& w_rad_s,
                                      const std::vector<std::complex<double>>& response,
                                      const LevyOptions& options = {});
LinkIdentification IdentifyLinkModels(const FrequencyResponseEstimate& estimate,
                                      const LevyOptions& options = {});

// Table 3's indices of given model parameters against the data (J from
// the parameters' N and D with the data's G = P / (j w)^options.
// integrator_order; the model's P uses params.integrator.order). Throws as
// the fits do.
FitIndices ComputeFitIndices(const std::vector<double>& w_rad_s,
                             const std::vector<std::complex<double>>& response,
                             const IpmcLinkParams& params, const LevyOptions& options = {});

}  // namespace ipmc
