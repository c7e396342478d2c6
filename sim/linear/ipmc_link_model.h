// Linear model of one IPMC link: voltage V [V] -> free tip deflection [mm]
// (paper section 4, eqs. 4-7, Table 2):
//
//   P_q(s) = H(s) G_q(s),  H(s) = s^-0.5                       (eq. 4)
//   G1(s) = a0 / (b2 s^2 + b1 s + 1)                           (eq. 5)
//   G2(s) = a0 / (b1 s^alpha + 1),  alpha in (1, 2) in the paper (eq. 6)
//
// Every fractional power is realised by an Oustaloup approximation
// (sim/linear/oustaloup.h) inside a finite state-space block:
//  - H(s): OustaloupStateSpace(integrator), a cascade of first-order
//    sections. Its DC gain is bounded only by the band: |H| -> w_b^-0.5 below
//    w_b, so w_b is the slowest time scale the model can represent
//    (1/w_b = 1000 s for the default w_b = 1e-3 rad/s, ten times the
//    100 s period of the paper's 0.01 Hz wave).
//  - G2(s): 1 / (b1 s^alpha + 1) is the unity negative feedback of
//    (1/b1) s^-alpha, realised strictly proper as s^m times an Oustaloup
//    block of s^f with m = round(-alpha), f = -alpha - m (for the paper's
//    alpha in (1.5, 2): s^-2 times an Oustaloup of s^(2-alpha)), then
//    scaled by a0.
// The link states are, in order: the s^-0.5 sections (scaled to unit DC
// gain, so they carry the input's scale), then for G1 the deflection y [mm]
// and dy/dt [mm/s]; for G2 the s^f sections, then |m| integrator states
// (for m = -2: the derivative of the lag's output before the gain a0, then
// that output).
//
// Table 2 gives b1 of G1 only for link 3 (eq. 7: b1 = 23.31e-3 s). Links 1
// and 2 take link 3's damping ratio zeta = b1 / (2 sqrt(b2)) = 0.2525
// (an assumption: the paper does not print their b1). G2's b1 is missing for
// all links; it is fitted here to the same link's G1 response over the
// paper's identification band [0.2, 50] rad/s with Table 2's G2 a0 and
// alpha held fixed (FitG2B1; constants kPaperG2B1). With only b1 free the
// fit is approximate: relative residuals 0.22 / 0.26 / 0.094 for links
// 1 / 2 / 3 (G2's resonance, fixed by alpha, is sharper than G1's).
#ifndef IPMC_SWIM_SIM_LINEAR_IPMC_LINK_MODEL_H_
#define IPMC_SWIM_SIM_LINEAR_IPMC_LINK_MODEL_H_

#include <complex>
#include <optional>
#include <string>

#include "sim/linear/oustaloup.h"
#include "sim/linear/state_space.h"

namespace ipmc {

enum class IpmcModelKind { kG1, kG2 };

// The largest |a0| a link accepts [mm/V]: over 2500 times Table 2's
// largest (0.376 mm/V), so any strip fits; a gain beyond it is a mistake
// that would carry the link models' states past the double range.
constexpr double kMaxStaticGain_mm_per_V = 1e3;

struct IpmcLinkParams {  // one link; SI except the paper's mm/V interface
  IpmcModelKind kind = IpmcModelKind::kG1;
  double a0_mm_per_V = 0;  // static gain of G, 0 < |a0| <= kMaxStaticGain_mm_per_V
  double b1 = 0;           // [s] for G1, [s^alpha] for G2; > 0
  double b2_s2 = 0;        // [s^2], G1 only; >= 0 (0 gives a first-order lag)
  double alpha = 1.8;      // G2's order, in (0, 2)
  // The s^-0.5 factor H(s). Band [1e-3, 1e3] rad/s: w_b sits 1.8 decades
  // below the 0.01 Hz (0.063 rad/s) swimming frequency and w_h 1.3 decades
  // above the model's 50 rad/s validity limit; n = 8 pairs. Against the
  // exact P_q over [0.05, 50] rad/s: 0.06 dB and 1.3 deg (the largest
  // phase error is the band-edge effect near 50 rad/s; 0.5 deg at 5 rad/s).
  // A wider band or more pairs add fast poles (the fastest is ~270 rad/s
  // here) that make every voltage change more expensive to integrate.
  // order must be < 1 (a proper realisation).
  OustaloupConfig integrator{-0.5, 1e-3, 1e3, 8};
  // G2's s^-alpha block: band, n and variant are used; its order is
  // ignored (LinkStateSpace uses -alpha). The feedback makes the closed
  // loop insensitive to the approximation far below the corner
  // b1^(-1/alpha) ~ 20-25 rad/s, so the band starts at 0.1 rad/s; with
  // n = 6 the G2 error over [0.05, 50] rad/s is 0.09 dB / 0.85 deg
  // (H included), and the fastest closed-loop pole is ~580 rad/s.
  OustaloupConfig fractional_lag{-1.8, 0.1, 1e3, 6};

  // Throws std::invalid_argument naming the field and its allowed range.
  void Validate() const;
};

// Table 2 parameters of link 1..3 for model G1 or G2 (a0 and b2 in the
// paper's units x 1e-3 converted to plain numbers). Throws
// std::invalid_argument for a link outside 1..3.
IpmcLinkParams PaperLinkParams(int link, IpmcModelKind kind);

// Which plant each link of a flagellum gets.
//  - kUniform: every link the control-design plant, link 3's model (eq. 7
//    for G1). Section 5.3 simulates three equal links "modeled with the
//    same dynamics since they have the same length"; Table 2's link-2 and
//    link-3 rows were measured at the tips of passive links while link 1
//    alone was driven (section 4.1), so they are not the links' own
//    actuators.
//  - kTable2: link q gets Table 2's row q (links beyond 3 repeat row 3).
enum class PlantAssignment { kUniform, kTable2 };

// "uniform" / "table2"; ParsePlantAssignment returns nullopt for any other
// word.
const char* PlantAssignmentName(PlantAssignment plants);
std::optional<PlantAssignment> ParsePlantAssignment(const std::string& word);

// Length of the links Table 2 was identified on [m] (Table 1).
constexpr double kPaperLinkLength_m = 10e-3;

// The model of a link of length_m [m], scaled from one identified on a
// link of kPaperLinkLength_m. Assumptions (the paper identifies 10 mm
// links only):
//  - a uniform electro-active bending moment M gives the curvature
//    M / (E I) whatever the length, so the free tip deflection
//    M L^2 / (2 E I) grows as L^2: a0 ~ L^2;
//  - the first bending mode of a clamped strip has w_1 = 3.516
//    sqrt(E I / (rho A L^4)) (Euler-Bernoulli), so w_1 ~ 1/L^2: b2 ~ L^4
//    for G1, and b1 ~ L^2 keeps its damping ratio b1 / (2 sqrt(b2));
//    for G2, whose corner is b1^(-1/alpha), b1 ~ L^(2 alpha).
// The Oustaloup bands are kept. A link of kPaperLinkLength_m is returned
// unchanged. Throws std::invalid_argument unless length_m is finite > 0.
IpmcLinkParams ScaleLinkToLength(IpmcLinkParams params, double length_m);

// Link q's (1-based) model under `plants`, scaled to its length.
IpmcLinkParams AssignedLinkParams(PlantAssignment plants, int link, IpmcModelKind kind,
                                  double length_m);

// Damping ratio of link 3's G1 (eq. 7), zeta = b1 / (2 sqrt(b2)) = 0.2525,
// which PaperLinkParams gives links 1 and 2: b1 = 2 zeta sqrt(b2).
double PaperG1DampingRatio();

// Fitted b1 [s^alpha] of G2 for links 1..3 (see FitG2B1 and the tests).
constexpr double kPaperG2B1[3] = {3.5138722245e-3, 3.2648319688e-3,
                                  5.8071123126e-3};

// State-space realisation of P_q (voltage in V, deflection out in mm).
StateSpace LinkStateSpace(const IpmcLinkParams& params);

// Exact fractional response P_q(j w) = (j w)^integrator.order G_q(j w)
// with (j w)^gamma = w^gamma exp(j gamma pi / 2); no Oustaloup.
std::complex<double> LinkResponseExact(const IpmcLinkParams& params,
                                       double w_rad_s);

struct G2Fit {
  double b1 = 0;  // [s^alpha]
  // sqrt(sum |G2 - G1|^2 / sum |G1|^2) over the frequency grid.
  double relative_residual = 0;
};

// Fits G2's b1 to a G1 link's response: minimises
// sum_i |G2(j w_i; b1) - G1(j w_i)|^2 over `points` log-spaced w_i in
// [w_min_rad_s, w_max_rad_s], with G2's a0 and alpha from `g2` and G1 from
// `g1` (only G, not the common factor H). Golden-section search on log(b1)
// after a coarse scan. Throws std::invalid_argument on invalid parameters.
G2Fit FitG2B1(const IpmcLinkParams& g1, const IpmcLinkParams& g2,
              double w_min_rad_s = 0.2, double w_max_rad_s = 50.0,
              int points = 200);

}  // namespace ipmc

#endif  // IPMC_SWIM_SIM_LINEAR_IPMC_LINK_MODEL_H_
