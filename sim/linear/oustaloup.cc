#include "sim/linear/oustaloup.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace ipmc {
namespace {

constexpr double kMaxAbsOrder = 20.0;
constexpr int kMaxN = 100;

[[noreturn]] void ThrowField(const char* field, const char* range,
                             double got) {
  std::ostringstream out;
  out << "oustaloup: " << field << " must be " << range << " (got " << got
      << ")";
  throw std::invalid_argument(out.str());
}

// First-order section (s + z) / (s + p) with the state scaled to unit DC
// gain: x' = -p x + p u, y = ((z - p) / p) x + u.
StateSpace FirstOrderSection(double z, double p) {
  StateSpace out;
  out.a = Eigen::MatrixXd::Constant(1, 1, -p);
  out.b = Eigen::MatrixXd::Constant(1, 1, p);
  out.c = Eigen::MatrixXd::Constant(1, 1, (z - p) / p);
  out.d = Eigen::MatrixXd::Constant(1, 1, 1.0);
  return out;
}

}  // namespace

void OustaloupConfig::Validate() const {
  if (!std::isfinite(order) || std::abs(order) > kMaxAbsOrder) {
    ThrowField("order", "finite with |order| <= 20", order);
  }
  if (!std::isfinite(w_high_rad_s) || w_high_rad_s <= 0) {
    ThrowField("w_high_rad_s", "finite and > 0", w_high_rad_s);
  }
  if (!std::isfinite(w_low_rad_s) || w_low_rad_s <= 0 ||
      w_low_rad_s >= w_high_rad_s) {
    std::ostringstream out;
    out << "oustaloup: w_low_rad_s must be > 0 and < w_high_rad_s (got "
        << w_low_rad_s << ", " << w_high_rad_s << ")";
    throw std::invalid_argument(out.str());
  }
  if (n < 1 || n > kMaxN) {
    ThrowField("n", "in [1, 100]", n);
  }
  if (variant != OustaloupVariant::kNPairs &&
      variant != OustaloupVariant::k2NPlus1) {
    ThrowField("variant", "kNPairs or k2NPlus1", static_cast<int>(variant));
  }
}

int OustaloupIntegerOrder(double order) {
  if (std::abs(order) < 1.0) return 0;
  return static_cast<int>(std::round(order));  // ties away from zero
}

double OustaloupFractionalOrder(double order) {
  return order - OustaloupIntegerOrder(order);
}

std::complex<double> ZeroPoleGain::Evaluate(std::complex<double> s) const {
  std::complex<double> h = gain;
  for (double z : zero_corners_rad_s) h *= s + z;
  for (double p : pole_corners_rad_s) h /= s + p;
  if (integer_order != 0) h *= std::pow(s, integer_order);
  return h;
}

ZeroPoleGain OustaloupZpk(const OustaloupConfig& config) {
  config.Validate();
  const double w_b = config.w_low_rad_s;
  const double w_h = config.w_high_rad_s;
  const double f = OustaloupFractionalOrder(config.order);
  ZeroPoleGain zpk;
  zpk.integer_order = OustaloupIntegerOrder(config.order);
  if (f == 0.0) return zpk;  // exact integer order: no corners, gain 1
  zpk.gain = std::pow(w_h, f);
  if (config.variant == OustaloupVariant::kNPairs) {
    // z_k = w_b w_u^((2k-1-f)/N), p_k = w_b w_u^((2k-1+f)/N), w_u^2 = w_h/w_b
    const double w_u = std::sqrt(w_h / w_b);
    const double n = config.n;
    for (int k = 1; k <= config.n; ++k) {
      zpk.zero_corners_rad_s.push_back(w_b * std::pow(w_u, (2 * k - 1 - f) / n));
      zpk.pole_corners_rad_s.push_back(w_b * std::pow(w_u, (2 * k - 1 + f) / n));
    }
  } else {
    // z_k = w_b (w_h/w_b)^((k+N+(1-f)/2)/(2N+1)), p_k with (1+f)/2, k=-N..N
    const double ratio = w_h / w_b;
    const double pairs = 2.0 * config.n + 1.0;
    for (int k = -config.n; k <= config.n; ++k) {
      const double base = k + config.n;
      zpk.zero_corners_rad_s.push_back(
          w_b * std::pow(ratio, (base + 0.5 * (1.0 - f)) / pairs));
      zpk.pole_corners_rad_s.push_back(
          w_b * std::pow(ratio, (base + 0.5 * (1.0 + f)) / pairs));
    }
  }
  return zpk;
}

StateSpace ZeroPoleGainStateSpace(const ZeroPoleGain& zpk) {
  if (zpk.zero_corners_rad_s.size() != zpk.pole_corners_rad_s.size()) {
    std::ostringstream out;
    out << "zero-pole-gain realisation: needs as many zero as pole corners (got "
        << zpk.zero_corners_rad_s.size() << " and " << zpk.pole_corners_rad_s.size() << ")";
    throw std::invalid_argument(out.str());
  }
  for (const std::vector<double>* corners : {&zpk.zero_corners_rad_s, &zpk.pole_corners_rad_s}) {
    for (double corner : *corners) {
      if (!std::isfinite(corner) || !(corner > 0)) {
        std::ostringstream out;
        out << "zero-pole-gain realisation: corners must be finite and > 0 (stable, "
               "minimum-phase sections), got "
            << corner;
        throw std::invalid_argument(out.str());
      }
    }
  }
  if (zpk.integer_order > 0) {
    std::ostringstream out;
    out << "zero-pole-gain realisation: integer order " << zpk.integer_order
        << " (a differentiator) is improper";
    throw std::invalid_argument(out.str());
  }
  StateSpace system = Gain(zpk.gain);
  for (std::size_t k = 0; k < zpk.zero_corners_rad_s.size(); ++k) {
    system = Series(system, FirstOrderSection(zpk.zero_corners_rad_s[k],
                                              zpk.pole_corners_rad_s[k]));
  }
  if (zpk.integer_order < 0) {
    system = Series(system, Integrators(-zpk.integer_order));
  }
  return system;
}

StateSpace OustaloupStateSpace(const OustaloupConfig& config) {
  const ZeroPoleGain zpk = OustaloupZpk(config);
  if (zpk.integer_order > 0) {
    std::ostringstream out;
    out << "oustaloup: order " << config.order << " has integer part "
        << zpk.integer_order
        << " (a differentiator), so its realisation is improper; realise "
           "s^order in a denominator by feedback instead";
    throw std::invalid_argument(out.str());
  }
  return ZeroPoleGainStateSpace(zpk);
}

}  // namespace ipmc
