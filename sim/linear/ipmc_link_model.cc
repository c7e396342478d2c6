#include "sim/linear/ipmc_link_model.h"
#include "sim/base/numbers.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace ipmc {
namespace {


// Table 2 (values printed x 1e-3) and eq. 7.
constexpr double kG1A0[3] = {13.70e-3, 51.00e-3, 376.09e-3};
constexpr double kG1B2[3] = {1.62e-3, 1.61e-3, 2.13e-3};
constexpr double kG1B1Link3 = 23.31e-3;  // eq. 7
constexpr double kG2Alpha[3] = {1.79, 1.81, 1.71};
constexpr double kG2A0[3] = {13.33e-3, 48.10e-3, 352.80e-3};

[[noreturn]] void ThrowField(const char* field, const char* range,
                             double got) {
  std::ostringstream out;
  out << "ipmc link: " << field << " must be " << range << " (got " << got
      << ")";
  throw std::invalid_argument(out.str());
}

void ValidateOustaloup(const char* field, const OustaloupConfig& config) {
  try {
    config.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("ipmc link: ") + field + ": " +
                                e.what());
  }
}

// (j w)^gamma = w^gamma exp(j gamma pi / 2), principal branch.
std::complex<double> FractionalPower(double w_rad_s, double gamma) {
  return std::polar(std::pow(w_rad_s, gamma), gamma * kPi / 2.0);
}

// G(j w) without the s^-0.5 factor.
std::complex<double> MechanicalResponse(const IpmcLinkParams& p,
                                        double w_rad_s) {
  const std::complex<double> s(0.0, w_rad_s);
  if (p.kind == IpmcModelKind::kG1) {
    return p.a0_mm_per_V / (p.b2_s2 * s * s + p.b1 * s + 1.0);
  }
  return p.a0_mm_per_V / (p.b1 * FractionalPower(w_rad_s, p.alpha) + 1.0);
}

// 1 / (b1 s^alpha + 1) as the unity negative feedback of (1/b1) s^-alpha,
// with s^-alpha = s^m * Oustaloup(s^f), m = round(-alpha), f = -alpha - m.
// The 1/b1 gain sits between the Oustaloup sections and the integrators so
// that the integrator states carry the output's scale.
StateSpace FractionalLag(const IpmcLinkParams& p) {
  OustaloupConfig fractional = p.fractional_lag;
  fractional.order = OustaloupFractionalOrder(-p.alpha);
  const int m = OustaloupIntegerOrder(-p.alpha);
  StateSpace forward =
      Series(OustaloupStateSpace(fractional), Gain(1.0 / p.b1));
  if (m < 0) forward = Series(forward, Integrators(-m));
  return Feedback(forward, Gain(1.0), -1.0);
}

double G2FitCost(const IpmcLinkParams& g1, IpmcLinkParams g2, double log_b1,
                 const std::vector<double>& w_rad_s) {
  g2.b1 = std::exp(log_b1);
  double cost = 0;
  for (double w : w_rad_s) {
    cost += std::norm(MechanicalResponse(g2, w) - MechanicalResponse(g1, w));
  }
  return cost;
}

}  // namespace

void IpmcLinkParams::Validate() const {
  if (kind != IpmcModelKind::kG1 && kind != IpmcModelKind::kG2) {
    ThrowField("kind", "kG1 or kG2", static_cast<int>(kind));
  }
  if (!(std::abs(a0_mm_per_V) <= kMaxStaticGain_mm_per_V) || a0_mm_per_V == 0) {
    ThrowField("a0_mm_per_V", "nonzero and in [-1000, 1000] mm/V", a0_mm_per_V);
  }
  if (!std::isfinite(b1) || b1 <= 0) {
    ThrowField("b1", "finite and > 0", b1);
  }
  if (!std::isfinite(b2_s2) || b2_s2 < 0) {
    ThrowField("b2_s2", "finite and >= 0", b2_s2);
  }
  if (!std::isfinite(alpha) || alpha <= 0 || alpha >= 2) {
    ThrowField("alpha", "in (0, 2)", alpha);
  }
  ValidateOustaloup("integrator", integrator);
  if (integrator.order >= 1) {
    ThrowField("integrator.order", "< 1 (a proper realisation)",
               integrator.order);
  }
  OustaloupConfig lag = fractional_lag;
  lag.order = -alpha;  // the order field is not used
  ValidateOustaloup("fractional_lag", lag);
}

double PaperG1DampingRatio() {
  return kG1B1Link3 / (2.0 * std::sqrt(kG1B2[2]));
}

IpmcLinkParams PaperLinkParams(int link, IpmcModelKind kind) {
  if (link < 1 || link > 3) ThrowField("link", "1, 2 or 3", link);
  const int i = link - 1;
  IpmcLinkParams p;
  p.kind = kind;
  if (kind == IpmcModelKind::kG1) {
    p.a0_mm_per_V = kG1A0[i];
    p.b2_s2 = kG1B2[i];
    p.b1 = link == 3 ? kG1B1Link3
                     : 2.0 * PaperG1DampingRatio() * std::sqrt(kG1B2[i]);
  } else {
    p.a0_mm_per_V = kG2A0[i];
    p.alpha = kG2Alpha[i];
    p.b1 = kPaperG2B1[i];
  }
  return p;
}

const char* PlantAssignmentName(PlantAssignment plants) {
  return plants == PlantAssignment::kUniform ? "uniform" : "table2";
}

std::optional<PlantAssignment> ParsePlantAssignment(const std::string& word) {
  if (word == "uniform") return PlantAssignment::kUniform;
  if (word == "table2") return PlantAssignment::kTable2;
  return std::nullopt;
}

IpmcLinkParams ScaleLinkToLength(IpmcLinkParams p, double length_m) {
  if (!std::isfinite(length_m) || !(length_m > 0)) ThrowField("length_m", "finite and > 0", length_m);
  if (length_m == kPaperLinkLength_m) return p;
  const double ratio = length_m / kPaperLinkLength_m;
  const double ratio2 = ratio * ratio;
  p.a0_mm_per_V *= ratio2;
  if (p.kind == IpmcModelKind::kG1) {
    p.b2_s2 *= ratio2 * ratio2;
    p.b1 *= ratio2;
  } else {
    p.b1 *= std::pow(ratio, 2.0 * p.alpha);
  }
  return p;
}

IpmcLinkParams AssignedLinkParams(PlantAssignment plants, int link, IpmcModelKind kind,
                                  double length_m) {
  const int row = plants == PlantAssignment::kUniform ? 3 : std::min(link, 3);
  return ScaleLinkToLength(PaperLinkParams(row, kind), length_m);
}

StateSpace LinkStateSpace(const IpmcLinkParams& params) {
  params.Validate();
  const StateSpace integrator = OustaloupStateSpace(params.integrator);
  if (params.kind == IpmcModelKind::kG1) {
    return Series(integrator, SecondOrderLag(params.a0_mm_per_V, params.b1,
                                             params.b2_s2));
  }
  return Series(integrator,
                Series(FractionalLag(params), Gain(params.a0_mm_per_V)));
}

std::complex<double> LinkResponseExact(const IpmcLinkParams& params,
                                       double w_rad_s) {
  params.Validate();
  if (!std::isfinite(w_rad_s) || w_rad_s <= 0) {
    ThrowField("w_rad_s", "finite and > 0", w_rad_s);
  }
  return FractionalPower(w_rad_s, params.integrator.order) *
         MechanicalResponse(params, w_rad_s);
}

G2Fit FitG2B1(const IpmcLinkParams& g1, const IpmcLinkParams& g2,
              double w_min_rad_s, double w_max_rad_s, int points) {
  if (g1.kind != IpmcModelKind::kG1 || g2.kind != IpmcModelKind::kG2) {
    throw std::invalid_argument(
        "ipmc link: FitG2B1 needs g1.kind == kG1 and g2.kind == kG2");
  }
  g1.Validate();
  IpmcLinkParams g2_checked = g2;
  g2_checked.b1 = 1.0;  // b1 is the unknown
  g2_checked.Validate();
  if (!(w_min_rad_s > 0) || !(w_max_rad_s > w_min_rad_s) ||
      !std::isfinite(w_max_rad_s)) {
    std::ostringstream out;
    out << "ipmc link: fit band must satisfy 0 < w_min_rad_s < w_max_rad_s "
           "(got "
        << w_min_rad_s << ", " << w_max_rad_s << ")";
    throw std::invalid_argument(out.str());
  }
  if (points < 2) ThrowField("points", ">= 2", points);

  std::vector<double> w_rad_s(points);
  double reference = 0;
  for (int i = 0; i < points; ++i) {
    w_rad_s[i] = w_min_rad_s *
                 std::pow(w_max_rad_s / w_min_rad_s, i / (points - 1.0));
    reference += std::norm(MechanicalResponse(g1, w_rad_s[i]));
  }

  // Coarse scan of log(b1) over six decades around the value that puts the
  // G2 corner b1^(-1/alpha) at G1's natural frequency 1/sqrt(b2) (or at
  // 1/b1 for a first-order G1).
  const double g1_corner_s = g1.b2_s2 > 0 ? std::sqrt(g1.b2_s2) : g1.b1;
  const double log_center = g2.alpha * std::log(g1_corner_s);
  const double log_span = 3.0 * std::log(10.0);
  constexpr int kScan = 241;
  const double step = 2.0 * log_span / (kScan - 1);
  int best = 0;
  double best_cost = INFINITY;
  for (int i = 0; i < kScan; ++i) {
    const double cost =
        G2FitCost(g1, g2, log_center - log_span + i * step, w_rad_s);
    if (cost < best_cost) {
      best_cost = cost;
      best = i;
    }
  }

  // Golden-section refinement in the bracket around the best scan point.
  const double inv_phi = (std::sqrt(5.0) - 1.0) / 2.0;
  double lo = log_center - log_span + (best - 1) * step;
  double hi = log_center - log_span + (best + 1) * step;
  double x1 = hi - inv_phi * (hi - lo);
  double x2 = lo + inv_phi * (hi - lo);
  double f1 = G2FitCost(g1, g2, x1, w_rad_s);
  double f2 = G2FitCost(g1, g2, x2, w_rad_s);
  while (hi - lo > 1e-12) {
    if (f1 < f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - inv_phi * (hi - lo);
      f1 = G2FitCost(g1, g2, x1, w_rad_s);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + inv_phi * (hi - lo);
      f2 = G2FitCost(g1, g2, x2, w_rad_s);
    }
  }
  const double log_b1 = 0.5 * (lo + hi);
  G2Fit fit;
  fit.b1 = std::exp(log_b1);
  fit.relative_residual =
      std::sqrt(G2FitCost(g1, g2, log_b1, w_rad_s) / reference);
  return fit;
}

}  // namespace ipmc
