// Travelling-wave references (eq. 2, eq. 3) and their projection onto the
// links. The joint points are found one link at a time: march along x from
// P_(q-1) to the first sample whose chord to P_(q-1) is at least s_q, then
// refine that bracket by safeguarded Newton (bisection whenever a Newton
// step would leave the bracket or converge too slowly) on
//   g(x) = (x - x_(q-1))^2 + (y(x) - y_(q-1))^2 - s_q^2.
// Since g(x_(q-1)) = -s_q^2 < 0 and g(x_(q-1) + s_q) >= 0, a crossing always
// exists in (x_(q-1), x_(q-1) + s_q]; the march makes it the first one, so
// a steep wave whose chord length is not monotonic in x still gives the
// nearest joint point along the body.
#include "sim/core/waveform.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "sim/base/error.h"
#include "sim/base/numbers.h"

namespace ipmc {
namespace {

constexpr double kMmPerUm = 1e-3;

// The march samples each chord search at least kMinMarchSteps times, and
// at least kStepsPerWavelength times per wavelength, but never more than
// kMaxMarchSteps times.
constexpr int kMinMarchSteps = 16;
constexpr double kStepsPerWavelength = 16.0;
constexpr int kMaxMarchSteps = 1024;
// Newton/bisection stops once a step is below this [mm].
constexpr double kRootStep_mm = 1e-13;
constexpr int kMaxRootIterations = 200;

void RequireFinite(const char* field, double value) {
  if (!std::isfinite(value)) {
    throw FieldError(std::string("waveform: ") + field + " must be finite (got " +
                         FormatDouble(value) + ")",
                     field, "finite");
  }
}

void RequirePositiveLength(const char* field, int index, double value) {
  if (!std::isfinite(value) || !(value > 0.0)) {
    throw std::invalid_argument(std::string("waveform: geometry.") + field + "[" +
                                std::to_string(index) + "] must be finite and > 0 (got " +
                                FormatDouble(value) + ")");
  }
}

void ValidateGeometry(const LinkGeometry& geometry) {
  if (geometry.pitch_mm.empty()) {
    throw std::invalid_argument("waveform: geometry.pitch_mm must not be empty");
  }
  if (geometry.length_mm.size() != geometry.pitch_mm.size()) {
    throw std::invalid_argument(
        "waveform: geometry.length_mm must have one entry per link, like pitch_mm (got " +
        std::to_string(geometry.length_mm.size()) + " and " +
        std::to_string(geometry.pitch_mm.size()) + ")");
  }
  for (std::size_t q = 0; q < geometry.pitch_mm.size(); ++q) {
    RequirePositiveLength("pitch_mm", static_cast<int>(q), geometry.pitch_mm[q]);
    RequirePositiveLength("length_mm", static_cast<int>(q), geometry.length_mm[q]);
  }
}

// The wave frozen at one instant; the configuration must be valid. Both
// WaveY_um and the discretisation evaluate y through Y_um, so joint points
// lie on WaveY_um bit for bit.
class FrozenWave {
 public:
  FrozenWave(const WaveformConfig& wave, double t_s)
      : wave_(wave),
        wavenumber_per_mm_(kTwoPi / wave.wavelength_mm),
        cycles_(wave.frequency_Hz * t_s) {}

  // sin(2 pi / lambda (x - Vp t)) = sin(2 pi (x / lambda - f t)), Vp = lambda f.
  double Phase(double x_mm) const { return kTwoPi * (x_mm / wave_.wavelength_mm - cycles_); }

  double Envelope_um(double x_mm) const {
    if (wave_.kind == WaveformKind::kPolynomial) {
      return wave_.c0_um + (wave_.c1_um_per_mm + wave_.c2_um_per_mm2 * x_mm) * x_mm;
    }
    return wave_.c_um * std::pow(x_mm, wave_.alpha);
  }

  double MaxAbsEnvelope_um(double a_mm, double b_mm) const {
    const double x = std::max(std::abs(a_mm), std::abs(b_mm));
    if (wave_.kind == WaveformKind::kPolynomial) {
      return std::abs(wave_.c0_um) + (std::abs(wave_.c1_um_per_mm) + std::abs(wave_.c2_um_per_mm2) * x) * x;
    }
    return std::abs(wave_.c_um) * std::pow(b_mm, wave_.alpha);
  }

  double EnvelopeSlope_um_per_mm(double x_mm) const {
    if (wave_.kind == WaveformKind::kPolynomial) {
      return wave_.c1_um_per_mm + 2.0 * wave_.c2_um_per_mm2 * x_mm;
    }
    // Only evaluated at x > 0, where x^(alpha - 1) is finite.
    return wave_.c_um * wave_.alpha * std::pow(x_mm, wave_.alpha - 1.0);
  }

  double Y_um(double x_mm) const { return Envelope_um(x_mm) * std::sin(Phase(x_mm)); }
  double Y_mm(double x_mm) const { return Y_um(x_mm) * kMmPerUm; }

  // Y_mm and Slope at x > 0 from one phase, its sine and its cosine: the
  // same expressions, so the same numbers bit for bit.
  void YAndSlope(double x_mm, double* y_mm, double* slope) const {
    const double phase = Phase(x_mm);
    const double sine = std::sin(phase);
    const double envelope_um = Envelope_um(x_mm);
    *y_mm = envelope_um * sine * kMmPerUm;
    *slope = (EnvelopeSlope_um_per_mm(x_mm) * sine +
              envelope_um * wavenumber_per_mm_ * std::cos(phase)) *
             kMmPerUm;
  }

  // Upper bounds on |y| [mm] and on |dy/dx| over [a, b], with a >= 0 for
  // the fractional wave (whose slope is unbounded at x = 0: infinity).
  // Polynomial: |E(x)| <= |c0| + |c1| X + |c2| X^2, |E'(x)| <= |c1| + 2 |c2| X
  // with X = max(|a|, |b|); fractional: |E| <= |c| b^alpha, and
  // |E'| <= |c| alpha a^(alpha - 1) (alpha <= 1). |dy/dx| <= |E'| + |E| k.
  double MaxAbsY_mm(double a_mm, double b_mm) const { return MaxAbsEnvelope_um(a_mm, b_mm) * kMmPerUm; }
  double MaxAbsSlope(double a_mm, double b_mm) const {
    const double x = std::max(std::abs(a_mm), std::abs(b_mm));
    double envelope_slope = 0.0;
    if (wave_.kind == WaveformKind::kPolynomial) {
      envelope_slope = std::abs(wave_.c1_um_per_mm) + 2.0 * std::abs(wave_.c2_um_per_mm2) * x;
    } else if (wave_.c_um != 0.0) {
      if (!(a_mm > 0.0) && wave_.alpha < 1.0) return std::numeric_limits<double>::infinity();
      envelope_slope = std::abs(wave_.c_um) * wave_.alpha * std::pow(a_mm, wave_.alpha - 1.0);
    }
    return (envelope_slope + MaxAbsEnvelope_um(a_mm, b_mm) * wavenumber_per_mm_) * kMmPerUm;
  }

  // dy/dx [mm/mm] at x > 0.
  double Slope(double x_mm) const {
    const double phase = Phase(x_mm);
    return (EnvelopeSlope_um_per_mm(x_mm) * std::sin(phase) +
            Envelope_um(x_mm) * wavenumber_per_mm_ * std::cos(phase)) *
           kMmPerUm;
  }

 private:
  const WaveformConfig& wave_;
  double wavenumber_per_mm_;
  double cycles_;
};

// Squared chord from (x0, y0) to the wave at x, minus s^2, and its slope.
struct ChordResidual {
  const FrozenWave& wave;
  double x0_mm, y0_mm, pitch_mm;

  double Value(double x_mm) const {
    const double dx = x_mm - x0_mm;
    const double dy = wave.Y_mm(x_mm) - y0_mm;
    return dx * dx + dy * dy - pitch_mm * pitch_mm;
  }
  double Slope(double x_mm) const {
    return 2.0 * (x_mm - x0_mm) + 2.0 * (wave.Y_mm(x_mm) - y0_mm) * wave.Slope(x_mm);
  }
  // Value and Slope together, bit for bit, from one YAndSlope.
  void ValueAndSlope(double x_mm, double* value, double* slope) const {
    double y_mm = 0.0, wave_slope = 0.0;
    wave.YAndSlope(x_mm, &y_mm, &wave_slope);
    const double dx = x_mm - x0_mm;
    const double dy = y_mm - y0_mm;
    *value = dx * dx + dy * dy - pitch_mm * pitch_mm;
    *slope = 2.0 * (x_mm - x0_mm) + 2.0 * (y_mm - y0_mm) * wave_slope;
  }
};

// Root of `residual` in [lo, hi] given g_lo = residual(lo) < 0 < g_hi =
// residual(hi), by safeguarded Newton from the secant point of the bracket.
double RefineCrossing(const ChordResidual& residual, double lo, double g_lo, double hi,
                      double g_hi) {
  double x = lo + (hi - lo) * (g_lo / (g_lo - g_hi));
  if (!(x > lo && x < hi)) x = 0.5 * (lo + hi);
  double step = hi - lo;
  double previous_step = step;
  double g = 0.0, dg = 0.0;
  residual.ValueAndSlope(x, &g, &dg);
  for (int iteration = 0; iteration < kMaxRootIterations; ++iteration) {
    if (g == 0.0) return x;
    if (g < 0.0) {
      lo = x;
    } else {
      hi = x;
    }
    const double newton_x = x - g / dg;
    // Converged: the Newton step is below the tolerance, so the error of
    // newton_x is of the order of its square.
    if (std::abs(newton_x - x) < kRootStep_mm) return newton_x;
    const bool newton_inside = std::isfinite(newton_x) && newton_x > lo && newton_x < hi;
    if (newton_inside && std::abs(2.0 * g) <= std::abs(previous_step * dg)) {
      previous_step = step;
      step = newton_x - x;
      x = newton_x;
    } else {
      previous_step = step;
      step = 0.5 * (hi - lo);
      x = lo + step;
    }
    if (std::abs(step) < kRootStep_mm || x <= lo || x >= hi) return x;
    residual.ValueAndSlope(x, &g, &dg);
  }
  return x;
}

// x of the first point beyond x0 at chord length `pitch_mm` from (x0, y0).
double NextJointX(const FrozenWave& wave, double wavelength_mm, double x0_mm, double y0_mm,
                  double pitch_mm) {
  const ChordResidual residual{wave, x0_mm, y0_mm, pitch_mm};
  const double steps_by_wavelength = std::ceil(kStepsPerWavelength * pitch_mm / wavelength_mm);
  const int steps =
      static_cast<int>(std::clamp(steps_by_wavelength, static_cast<double>(kMinMarchSteps),
                                  static_cast<double>(kMaxMarchSteps)));
  const auto sample_x = [&](int k) {
    // The last sample is exactly x0 + s, where the chord is at least s.
    return k == steps ? x0_mm + pitch_mm : x0_mm + pitch_mm * k / steps;
  };
  // Samples closer to x0 than `inside_mm` lie strictly inside the circle
  // of radius s around (x0, y0), where the residual is negative: with
  // |y(x) - y0| <= min(Y + |y0|, L (x - x0)), Y and L bounding |y| and
  // |dy/dx| on [x0, x0 + s], the chord is below s while
  // dx < max(sqrt(s^2 - (Y + |y0|)^2), s / sqrt(1 + L^2)). Skipping them
  // (with a margin far above rounding) leaves the first crossing, and the
  // bracket around it, as the full march gives them.
  const double reach_mm = wave.MaxAbsY_mm(x0_mm, x0_mm + pitch_mm) + std::abs(y0_mm);
  const double slope = wave.MaxAbsSlope(x0_mm, x0_mm + pitch_mm);
  double inside_mm = std::isfinite(slope) ? pitch_mm / std::sqrt(1.0 + slope * slope) : 0.0;
  if (reach_mm < pitch_mm) {
    inside_mm = std::max(inside_mm, std::sqrt(pitch_mm * pitch_mm - reach_mm * reach_mm));
  }
  inside_mm *= 1.0 - 1e-9;
  int first = 1;
  while (first < steps && sample_x(first) - x0_mm < inside_mm) ++first;
  double lo = first == 1 ? x0_mm : sample_x(first - 1);
  double g_lo = first == 1 ? -pitch_mm * pitch_mm : residual.Value(lo);
  for (int k = first; k <= steps; ++k) {
    const double hi = sample_x(k);
    const double g = residual.Value(hi);
    if (g >= 0.0) return g == 0.0 ? hi : RefineCrossing(residual, lo, g_lo, hi, g);
    lo = hi;
    g_lo = g;
  }
  // Unreachable for finite values: at x0 + s the chord is at least s.
  return x0_mm + pitch_mm;
}

}  // namespace

void WaveformConfig::Validate() const {
  if (kind != WaveformKind::kPolynomial && kind != WaveformKind::kFractional) {
    throw FieldError("waveform: kind must be kPolynomial or kFractional (got " +
                         std::to_string(static_cast<int>(kind)) + ")",
                     "kind", "kPolynomial or kFractional");
  }
  RequireFinite("c0_um", c0_um);
  RequireFinite("c1_um_per_mm", c1_um_per_mm);
  RequireFinite("c2_um_per_mm2", c2_um_per_mm2);
  RequireFinite("c_um", c_um);
  if (kind == WaveformKind::kFractional && !(alpha > 0.0 && alpha <= 1.0)) {
    throw FieldError("waveform: alpha must be in (0, 1] for the fractional wave (got " +
                         FormatDouble(alpha) + ")",
                     "alpha", "in (0, 1]");
  }
  if (!std::isfinite(frequency_Hz) || frequency_Hz == 0.0) {
    throw FieldError("waveform: frequency_Hz must be finite and != 0 (got " +
                         FormatDouble(frequency_Hz) + ")",
                     "frequency_Hz", "finite and != 0");
  }
  if (!std::isfinite(wavelength_mm) || !(wavelength_mm > 0.0)) {
    throw FieldError("waveform: wavelength_mm must be finite and > 0 (got " +
                         FormatDouble(wavelength_mm) + ")",
                     "wavelength_mm", "finite and > 0");
  }
}

double StartRamp(double t_s, double ramp_s) {
  if (t_s >= ramp_s) return 1.0;
  return 0.5 * (1.0 - std::cos(kPi * t_s / ramp_s));
}

double WaveY_um(const WaveformConfig& wave, double x_mm, double t_s) {
  wave.Validate();
  RequireFinite("x_mm", x_mm);
  RequireFinite("t_s", t_s);
  if (wave.kind == WaveformKind::kFractional && x_mm < 0.0) {
    throw std::invalid_argument("waveform: x_mm must be >= 0 for the fractional wave (got " +
                                FormatDouble(x_mm) + ")");
  }
  return FrozenWave(wave, t_s).Y_um(x_mm);
}

LinkGeometry PaperLinkGeometry() {
  LinkGeometry geometry;
  geometry.length_mm = {10.0, 10.0, 10.0};
  // Hinges at x = 0, 10.25 and 20.75 mm; the tip of link 3 at 31 mm.
  geometry.pitch_mm = {10.25, 10.5, 10.25};
  return geometry;
}

DiscreteWave DiscretiseWave(const WaveformConfig& wave, const LinkGeometry& geometry, double t_s) {
  wave.Validate();
  ValidateGeometry(geometry);
  RequireFinite("t_s", t_s);

  const FrozenWave frozen(wave, t_s);
  const std::size_t links = geometry.pitch_mm.size();
  DiscreteWave out;
  out.joint_x_mm.resize(links + 1);
  out.joint_y_mm.resize(links + 1);
  out.relative_deflection_mm.resize(links);

  double x = 0.0;
  double y = frozen.Y_mm(x);
  double previous_angle_rad = 0.0;  // phi_0
  out.joint_x_mm[0] = x;
  out.joint_y_mm[0] = y;
  for (std::size_t q = 0; q < links; ++q) {
    const double next_x = NextJointX(frozen, wave.wavelength_mm, x, y, geometry.pitch_mm[q]);
    const double next_y = frozen.Y_mm(next_x);
    const double angle_rad = std::atan2(next_y - y, next_x - x);
    out.relative_deflection_mm[q] =
        geometry.length_mm[q] * std::sin(angle_rad - previous_angle_rad);
    out.joint_x_mm[q + 1] = next_x;
    out.joint_y_mm[q + 1] = next_y;
    x = next_x;
    y = next_y;
    previous_angle_rad = angle_rad;
  }
  return out;
}

}  // namespace ipmc
