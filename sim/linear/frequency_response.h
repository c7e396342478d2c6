// Frequency-response tools for single-input single-output loops: Bode data
// on a logarithmic grid, gain and phase crossovers, stability margins, and
// CSV output.
//
// A frequency function maps an angular frequency w [rad/s] to the complex
// value H(j w). Conventions:
//  - magnitude in dB: 20 log10 |H(j w)|;
//  - phase in degrees, unwrapped along increasing w: the first grid point
//    takes arg H in (-180, 180], each following point the branch within
//    180 deg of its predecessor. The grid must resolve the phase (no jump
//    of 180 deg or more between neighbours) for the unwrapping to hold.
//  - gain crossover: |L(j w)| = 1; phase crossover: L(j w) on the negative
//    real axis (unwrapped phase = -180 deg + k 360 deg);
//  - phase margin PM = 180 deg + arg L(j w_gc), reported in (-180, 180];
//    gain margin GM = -20 log10 |L(j w_pc)| [dB].
//
// Crossovers are bracketed on a logarithmic search grid and refined on
// log10 w by TOMS Algorithm 748 (BracketedRoot below), so a crossing that
// the grid does not resolve (two crossings within one grid step) is
// missed: choose `points_per_decade` accordingly.
#ifndef IPMC_SWIM_CONTROLLERS_FREQUENCY_RESPONSE_H_
#define IPMC_SWIM_CONTROLLERS_FREQUENCY_RESPONSE_H_

#include <complex>
#include <functional>
#include <optional>
#include <vector>

namespace ipmc {

// H(j w) for w in rad/s.
using FrequencyFunction = std::function<std::complex<double>(double w_rad_s)>;

// 20 log10 |h| [dB].
double MagnitudeDb(std::complex<double> h);

// arg h [deg], in (-180, 180].
double PhaseDeg(std::complex<double> h);

// Logarithmic frequency grid: w_low, ..., w_high with `points_per_decade`
// points per decade (at least 2 points in all; the last point is w_high).
struct FrequencyGrid {
  double w_low_rad_s = 1e-3;
  double w_high_rad_s = 1e3;
  int points_per_decade = 100;

  // Throws std::invalid_argument naming the field: 0 < w_low < w_high, both
  // finite; 1 <= points_per_decade <= 100000.
  void Validate() const;
  std::vector<double> Frequencies() const;
};

// Bode data: parallel arrays of equal length.
struct BodeData {
  std::vector<double> w_rad_s;
  std::vector<double> magnitude_dB;
  std::vector<double> phase_deg;  // unwrapped along increasing w
};

// Evaluates `response` on `grid`. Throws std::invalid_argument for a bad
// grid and std::domain_error naming the frequency if H(j w) is zero or not
// finite there.
BodeData ComputeBode(const FrequencyFunction& response,
                     const FrequencyGrid& grid = {});

// One phase crossover and the gain margin it gives.
struct PhaseCrossover {
  double w_rad_s = 0;
  double gain_margin_dB = 0;  // -20 log10 |L(j w)|
};

struct StabilityMargins {
  // Every |L| = 1 crossing found in the search range, ascending.
  std::vector<double> gain_crossovers_rad_s;
  // Every phase crossover found in the search range, ascending.
  std::vector<PhaseCrossover> phase_crossovers;

  // The lowest gain crossover and its phase margin [deg] in (-180, 180];
  // empty if |L| never crosses 1 in the range.
  std::optional<double> gain_crossover_rad_s;
  std::optional<double> phase_margin_deg;

  // The gain margin closest to 0 dB among the phase crossovers (the most
  // critical one, as MATLAB's `margin` reports) and its frequency. Empty
  // ("no finite gain margin") when the phase never reaches -180 deg
  // (mod 360) within the search range.
  std::optional<double> gain_margin_dB;
  std::optional<double> phase_crossover_rad_s;
};

// Search range and resolution for ComputeMargins. The default range spans
// the paper's loops (crossovers of 5 to 40 rad/s) with ample room.
struct MarginSearch {
  FrequencyGrid grid{1e-4, 1e5, 200};
  // Stop the root search when the bracket in log10 w is this narrow.
  double log10_w_tolerance = 1e-12;

  // Throws std::invalid_argument naming the field.
  void Validate() const;
};

// Gain crossovers, phase crossovers, phase margin and gain margin of the
// open loop `loop`. Throws as ComputeBode does.
StabilityMargins ComputeMargins(const FrequencyFunction& loop,
                                const MarginSearch& search = {});

// Root of f on [a, b] (either order) by TOMS Algorithm 748 (G. E. Alefeld,
// F. A. Potra, Y. Shi, ACM Trans. Math. Softw. 21, 327, 1995: interpolation
// steps that keep the root bracketed), as Boost.Math's toms748_solve.
// f(a) and f(b) must have opposite signs or one of them be zero (that end
// is returned). Returns the midpoint of the final bracket, once that is at
// most `tolerance` (absolute, > 0) plus four ulps of its ends wide, or
// after 200 evaluations of f. Throws std::invalid_argument for a bad
// interval or tolerance, or a root that is not bracketed.
double BracketedRoot(const std::function<double(double)>& f, double a,
                     double b, double tolerance);

}  // namespace ipmc

#endif  // IPMC_SWIM_CONTROLLERS_FREQUENCY_RESPONSE_H_
