#include "sim/linear/frequency_response.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>

#include <boost/math/tools/toms748_solve.hpp>

#include "sim/base/numbers.h"

namespace ipmc {
namespace {

constexpr double kDegPerRad = 180.0 / kPi;
// Evaluations of f allowed to one root search; on the paper's loops TOMS 748
// narrows a grid step (0.005 decades) to 1e-12 decades in about 7.
constexpr std::uintmax_t kRootMaxEvaluations = 200;

// H(j w), checked to be finite and nonzero (so that dB and phase exist).
std::complex<double> EvaluateChecked(const FrequencyFunction& response,
                                     double w_rad_s) {
  const std::complex<double> h = response(w_rad_s);
  if (!std::isfinite(h.real()) || !std::isfinite(h.imag())) {
    throw std::domain_error("frequency response is not finite at w = " +
                            FormatDouble(w_rad_s) + " rad/s");
  }
  if (h == 0.0) {
    throw std::domain_error("frequency response is zero at w = " +
                            FormatDouble(w_rad_s) + " rad/s");
  }
  return h;
}

// Phase [deg] of h on the branch nearest to `anchor_deg` (within 180 deg),
// where `anchor_deg` is an unwrapped phase at a nearby frequency.
double PhaseNear(std::complex<double> h, double anchor_deg) {
  return anchor_deg + std::remainder(PhaseDeg(h) - anchor_deg, 360.0);
}

// Adds `root` unless it repeats the previous root (a crossing that lands
// exactly on a grid point can be bracketed from both sides).
void AppendRoot(std::vector<double>& roots, double root,
                double log10_tolerance) {
  if (!roots.empty() && std::abs(std::log10(root) - std::log10(roots.back())) <=
                            10 * log10_tolerance) {
    return;
  }
  roots.push_back(root);
}

}  // namespace

double MagnitudeDb(std::complex<double> h) {
  return 20.0 * std::log10(std::abs(h));
}

double PhaseDeg(std::complex<double> h) {
  const double phase = std::arg(h) * kDegPerRad;
  return phase <= -180.0 ? phase + 360.0 : phase;
}

void FrequencyGrid::Validate() const {
  if (!(w_low_rad_s > 0) || !std::isfinite(w_low_rad_s)) {
    throw std::invalid_argument(
        "FrequencyGrid.w_low_rad_s must be finite and > 0, got " +
        FormatDouble(w_low_rad_s));
  }
  if (!(w_high_rad_s > w_low_rad_s) || !std::isfinite(w_high_rad_s)) {
    throw std::invalid_argument(
        "FrequencyGrid.w_high_rad_s must be finite and > w_low_rad_s (" +
        FormatDouble(w_low_rad_s) + "), got " + FormatDouble(w_high_rad_s));
  }
  if (points_per_decade < 1 || points_per_decade > 100000) {
    throw std::invalid_argument(
        "FrequencyGrid.points_per_decade must be in [1, 100000], got " +
        std::to_string(points_per_decade));
  }
}

std::vector<double> FrequencyGrid::Frequencies() const {
  Validate();
  const double decades = std::log10(w_high_rad_s / w_low_rad_s);
  const int intervals =
      std::max(1, static_cast<int>(std::ceil(decades * points_per_decade)));
  std::vector<double> w(intervals + 1);
  for (int i = 0; i <= intervals; ++i) {
    w[i] = w_low_rad_s * std::pow(10.0, decades * i / intervals);
  }
  w.front() = w_low_rad_s;
  w.back() = w_high_rad_s;
  return w;
}

BodeData ComputeBode(const FrequencyFunction& response,
                     const FrequencyGrid& grid) {
  BodeData bode;
  bode.w_rad_s = grid.Frequencies();
  const std::size_t n = bode.w_rad_s.size();
  bode.magnitude_dB.resize(n);
  bode.phase_deg.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::complex<double> h = EvaluateChecked(response, bode.w_rad_s[i]);
    bode.magnitude_dB[i] = MagnitudeDb(h);
    bode.phase_deg[i] =
        i == 0 ? PhaseDeg(h) : PhaseNear(h, bode.phase_deg[i - 1]);
  }
  return bode;
}

void MarginSearch::Validate() const {
  grid.Validate();
  if (!(log10_w_tolerance > 0) || !(log10_w_tolerance < 1e-2)) {
    throw std::invalid_argument(
        "MarginSearch.log10_w_tolerance must be in (0, 1e-2), got " +
        FormatDouble(log10_w_tolerance));
  }
}

double BracketedRoot(const std::function<double(double)>& f, double a,
                     double b, double tolerance) {
  if (!(tolerance > 0) || !std::isfinite(tolerance)) {
    throw std::invalid_argument(
        "BracketedRoot: tolerance must be finite and > 0, got " +
        FormatDouble(tolerance));
  }
  if (!std::isfinite(a) || !std::isfinite(b) || a == b) {
    throw std::invalid_argument("BracketedRoot: [a, b] must be finite with a "
                                "!= b, got [" +
                                FormatDouble(a) + ", " + FormatDouble(b) + "]");
  }
  if (b < a) std::swap(a, b);
  const double fa = f(a);
  const double fb = f(b);
  if (fa == 0) return a;
  if (fb == 0) return b;
  if ((fa > 0) == (fb > 0) || !std::isfinite(fa) || !std::isfinite(fb)) {
    throw std::invalid_argument("BracketedRoot: root not bracketed on [" +
                                FormatDouble(a) + ", " + FormatDouble(b) + "]");
  }
  // Done when the bracket is `tolerance` wide, plus a few ulps of its ends
  // so that a tolerance below the spacing of doubles there still ends.
  const auto narrow_enough = [tolerance](double lo, double hi) {
    const double ulps = 4 * std::numeric_limits<double>::epsilon() *
                        std::max(std::abs(lo), std::abs(hi));
    return hi - lo <= tolerance + ulps;
  };
  std::uintmax_t evaluations = kRootMaxEvaluations;
  const std::pair<double, double> bracket = boost::math::tools::toms748_solve(
      f, a, b, fa, fb, narrow_enough, evaluations);
  // An exact zero comes back as a degenerate bracket, so the midpoint is it.
  return 0.5 * (bracket.first + bracket.second);
}

StabilityMargins ComputeMargins(const FrequencyFunction& loop,
                                const MarginSearch& search) {
  search.Validate();
  const BodeData bode = ComputeBode(loop, search.grid);
  const std::size_t n = bode.w_rad_s.size();
  const double tolerance = search.log10_w_tolerance;
  StabilityMargins margins;

  // Gain crossovers: sign changes of 20 log10 |L|.
  std::vector<double> gain_crossovers;
  std::vector<double> gain_crossover_phase_deg;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const bool above_lo = bode.magnitude_dB[i] >= 0;
    const bool above_hi = bode.magnitude_dB[i + 1] >= 0;
    if (above_lo == above_hi) continue;
    const double x = BracketedRoot(
        [&](double log10_w) {
          return MagnitudeDb(EvaluateChecked(loop, std::pow(10.0, log10_w)));
        },
        std::log10(bode.w_rad_s[i]), std::log10(bode.w_rad_s[i + 1]),
        tolerance);
    const double w = std::pow(10.0, x);
    const std::size_t before = gain_crossovers.size();
    AppendRoot(gain_crossovers, w, tolerance);
    if (gain_crossovers.size() > before) {
      gain_crossover_phase_deg.push_back(
          PhaseNear(EvaluateChecked(loop, w), bode.phase_deg[i]));
    }
  }
  margins.gain_crossovers_rad_s = gain_crossovers;
  if (!gain_crossovers.empty()) {
    margins.gain_crossover_rad_s = gain_crossovers.front();
    double pm = std::remainder(180.0 + gain_crossover_phase_deg.front(), 360.0);
    if (pm <= -180.0) pm += 360.0;
    margins.phase_margin_deg = pm;
  }

  // Phase crossovers: the unwrapped phase passes -180 + 360 k.
  std::vector<double> phase_crossovers;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double turns_lo = std::floor((bode.phase_deg[i] + 180.0) / 360.0);
    const double turns_hi = std::floor((bode.phase_deg[i + 1] + 180.0) / 360.0);
    if (turns_lo == turns_hi) continue;
    const double level = -180.0 + 360.0 * std::max(turns_lo, turns_hi);
    const double anchor_deg = bode.phase_deg[i];
    const double x = BracketedRoot(
        [&](double log10_w) {
          return PhaseNear(EvaluateChecked(loop, std::pow(10.0, log10_w)),
                           anchor_deg) -
                 level;
        },
        std::log10(bode.w_rad_s[i]), std::log10(bode.w_rad_s[i + 1]),
        tolerance);
    AppendRoot(phase_crossovers, std::pow(10.0, x), tolerance);
  }
  for (const double w : phase_crossovers) {
    PhaseCrossover crossover;
    crossover.w_rad_s = w;
    crossover.gain_margin_dB = -MagnitudeDb(EvaluateChecked(loop, w));
    margins.phase_crossovers.push_back(crossover);
    if (!margins.gain_margin_dB || std::abs(crossover.gain_margin_dB) <
                                       std::abs(*margins.gain_margin_dB)) {
      margins.gain_margin_dB = crossover.gain_margin_dB;
      margins.phase_crossover_rad_s = w;
    }
  }
  return margins;
}

}  // namespace ipmc
