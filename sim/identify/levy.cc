#include "sim/identify/levy.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "sim/base/numbers.h"

namespace ipmc {
namespace {

using Complex = std::complex<double>;

constexpr int kMinimumBandPoints = 3;

[[noreturn]] void Throw(const std::string& message) {
  throw std::invalid_argument("levy: " + message);
}

// (j w)^g on the principal branch.
Complex JwPower(double w_rad_s, double order) {
  return std::polar(std::pow(w_rad_s, order), order * kPi / 2);
}

// The band's data: the measured G (integrator removed) and P.
struct BandData {
  std::vector<double> w;
  std::vector<Complex> p;  // measured P
  std::vector<Complex> g;  // P / (j w)^h
};

BandData SelectBand(const std::vector<double>& w_rad_s, const std::vector<Complex>& response,
                    const LevyOptions& options) {
  options.Validate();
  if (w_rad_s.size() != response.size()) {
    Throw("response has " + std::to_string(response.size()) + " points, w_rad_s " +
          std::to_string(w_rad_s.size()));
  }
  if (w_rad_s.empty()) Throw("w_rad_s is empty");
  for (std::size_t i = 0; i < w_rad_s.size(); ++i) {
    if (!std::isfinite(w_rad_s[i]) || !(w_rad_s[i] > 0) ||
        (i > 0 && !(w_rad_s[i] > w_rad_s[i - 1]))) {
      Throw("w_rad_s must be finite, > 0 and strictly increasing (point " + std::to_string(i) +
            " is " + FormatDouble(w_rad_s[i]) + ")");
    }
    if (!std::isfinite(response[i].real()) || !std::isfinite(response[i].imag())) {
      Throw("response is not finite at point " + std::to_string(i) + " (w = " +
            FormatDouble(w_rad_s[i]) + " rad/s)");
    }
  }
  // A relative slack of 1e-9 lets a band given as the data's own end
  // points through despite rounding.
  const double slack = 1e-9;
  if (options.w_low_rad_s < w_rad_s.front() * (1 - slack) ||
      options.w_high_rad_s > w_rad_s.back() * (1 + slack)) {
    Throw("band [" + FormatDouble(options.w_low_rad_s) + ", " +
          FormatDouble(options.w_high_rad_s) + "] rad/s reaches outside the data [" +
          FormatDouble(w_rad_s.front()) + ", " + FormatDouble(w_rad_s.back()) + "] rad/s");
  }
  BandData band;
  for (std::size_t i = 0; i < w_rad_s.size(); ++i) {
    const double w = w_rad_s[i];
    if (w < options.w_low_rad_s * (1 - slack) || w > options.w_high_rad_s * (1 + slack)) continue;
    band.w.push_back(w);
    band.p.push_back(response[i]);
    band.g.push_back(response[i] / JwPower(w, options.integrator_order));
  }
  if (static_cast<int>(band.w.size()) < kMinimumBandPoints) {
    Throw("band [" + FormatDouble(options.w_low_rad_s) + ", " +
          FormatDouble(options.w_high_rad_s) + "] rad/s holds " + std::to_string(band.w.size()) +
          " points, fewer than " + std::to_string(kMinimumBandPoints));
  }
  return band;
}

// D(j w) of G1 or G2.
Complex Denominator(const IpmcLinkParams& params, double w) {
  if (params.kind == IpmcModelKind::kG1) {
    return Complex(1.0 - params.b2_s2 * w * w, params.b1 * w);
  }
  return 1.0 + params.b1 * JwPower(w, params.alpha);
}

// Mechanical part G(j w) = N / D of a fit (no validation).
Complex MechanicalResponse(const IpmcLinkParams& params, double w) {
  return params.a0_mm_per_V / Denominator(params, w);
}

// Least squares over real parameters: minimise sum_k |sum_j theta_j
// basis_j(k) - target(k)|^2 with complex basis and target. Returns theta.
Eigen::VectorXd SolveComplexLeastSquares(const std::vector<std::vector<Complex>>& basis,
                                         const std::vector<Complex>& target) {
  const int points = static_cast<int>(target.size());
  const int unknowns = static_cast<int>(basis.size());
  Eigen::MatrixXd a(2 * points, unknowns);
  Eigen::VectorXd b(2 * points);
  for (int k = 0; k < points; ++k) {
    b(2 * k) = target[k].real();
    b(2 * k + 1) = target[k].imag();
    for (int j = 0; j < unknowns; ++j) {
      a(2 * k, j) = basis[j][k].real();
      a(2 * k + 1, j) = basis[j][k].imag();
    }
  }
  // Scale the columns to unit norm: b1 and b2 multiply w and w^2.
  Eigen::VectorXd scale(unknowns);
  for (int j = 0; j < unknowns; ++j) {
    const double norm = a.col(j).norm();
    scale(j) = norm > 0 ? 1.0 / norm : 1.0;
    a.col(j) *= scale(j);
  }
  const Eigen::VectorXd scaled = a.colPivHouseholderQr().solve(b);
  return scaled.cwiseProduct(scale);
}

bool IsStable(const IpmcLinkParams& params) {
  if (params.kind == IpmcModelKind::kG1) {
    return params.b1 > 0 && params.b2_s2 >= 0 && std::isfinite(params.b1) &&
           std::isfinite(params.b2_s2);
  }
  return params.b1 > 0 && std::isfinite(params.b1) && params.alpha < 2;
}

FitIndices Indices(const BandData& band, const IpmcLinkParams& params) {
  FitIndices indices;
  const int points = static_cast<int>(band.w.size());
  indices.points = points;
  indices.w_first_rad_s = band.w.front();
  indices.w_last_rad_s = band.w.back();
  Complex mean = 0.0;
  for (const Complex& p : band.p) mean += p;
  mean /= static_cast<double>(points);
  double squared = 0.0, absolute = 0.0, maximum = 0.0, total = 0.0, levy = 0.0;
  for (int k = 0; k < points; ++k) {
    const double w = band.w[k];
    const Complex d = Denominator(params, w);
    levy += std::norm(band.g[k] * d - params.a0_mm_per_V);
    const Complex error = band.p[k] - FittedResponse(params, w);
    squared += std::norm(error);
    absolute += std::abs(error);
    maximum = std::max(maximum, std::abs(error));
    total += std::norm(band.p[k] - mean);
  }
  indices.levy_cost = levy;
  indices.mse = squared / points;
  indices.mad = absolute / points;
  indices.max_deviation = maximum;
  indices.r_squared = total > 0 ? 1.0 - squared / total : 0.0;
  return indices;
}

IpmcLinkParams FitTemplate(IpmcModelKind kind, const LevyOptions& options) {
  IpmcLinkParams params;
  params.kind = kind;
  params.integrator.order = options.integrator_order;
  return params;
}

// The fitted link of `kind`: a0 = theta(0), b1 = theta(1), `b2_s2` and,
// if given, `alpha`; its stability and its indices over the band.
LinkModelFit FittedLink(const BandData& band, IpmcModelKind kind, const Eigen::VectorXd& theta,
                        double b2_s2, std::optional<double> alpha, const LevyOptions& options) {
  LinkModelFit fit;
  fit.params = FitTemplate(kind, options);
  fit.params.a0_mm_per_V = theta(0);
  fit.params.b1 = theta(1);
  fit.params.b2_s2 = b2_s2;
  if (alpha) fit.params.alpha = *alpha;
  fit.stable = IsStable(fit.params);
  fit.indices = Indices(band, fit.params);
  return fit;
}

LinkModelFit FitG1(const BandData& band, const LevyOptions& options) {
  // G (1 + b1 s + b2 s^2) - a0 = 0  =>  a0 (-1) + b1 (s G) + b2 (s^2 G) = -G.
  const std::size_t points = band.w.size();
  std::vector<std::vector<Complex>> basis(3, std::vector<Complex>(points));
  std::vector<Complex> target(points);
  for (std::size_t k = 0; k < points; ++k) {
    const Complex s(0.0, band.w[k]);
    basis[0][k] = -1.0;
    basis[1][k] = s * band.g[k];
    basis[2][k] = s * s * band.g[k];
    target[k] = -band.g[k];
  }
  const Eigen::VectorXd theta = SolveComplexLeastSquares(basis, target);
  return FittedLink(band, IpmcModelKind::kG1, theta, theta(2), std::nullopt, options);
}

LinkModelFit FitG2(const BandData& band, double alpha, const LevyOptions& options) {
  // G (1 + b1 s^alpha) - a0 = 0  =>  a0 (-1) + b1 (s^alpha G) = -G.
  const std::size_t points = band.w.size();
  std::vector<std::vector<Complex>> basis(2, std::vector<Complex>(points));
  std::vector<Complex> target(points);
  for (std::size_t k = 0; k < points; ++k) {
    basis[0][k] = -1.0;
    basis[1][k] = JwPower(band.w[k], alpha) * band.g[k];
    target[k] = -band.g[k];
  }
  const Eigen::VectorXd theta = SolveComplexLeastSquares(basis, target);
  return FittedLink(band, IpmcModelKind::kG2, theta, 0.0, alpha, options);
}

}  // namespace

void LevyOptions::Validate() const {
  if (!std::isfinite(w_low_rad_s) || !std::isfinite(w_high_rad_s) || !(w_low_rad_s > 0) ||
      !(w_high_rad_s > w_low_rad_s)) {
    Throw("band must satisfy 0 < w_low_rad_s < w_high_rad_s, both finite (got [" +
          FormatDouble(w_low_rad_s) + ", " + FormatDouble(w_high_rad_s) + "])");
  }
  if (!std::isfinite(integrator_order) || std::abs(integrator_order) > 2) {
    Throw("integrator_order must be in [-2, 2] (got " + FormatDouble(integrator_order) + ")");
  }
  if (!std::isfinite(alpha_step) || alpha_step < 1e-4 || alpha_step > 0.5) {
    Throw("alpha_step must be in [1e-4, 0.5] (got " + FormatDouble(alpha_step) + ")");
  }
}

std::complex<double> FittedResponse(const IpmcLinkParams& params, double w_rad_s) {
  return JwPower(w_rad_s, params.integrator.order) * MechanicalResponse(params, w_rad_s);
}

LinkModelFit FitG1Levy(const std::vector<double>& w_rad_s, const std::vector<Complex>& response,
                       const LevyOptions& options) {
  return FitG1(SelectBand(w_rad_s, response, options), options);
}

LinkModelFit FitG2LevyAtOrder(const std::vector<double>& w_rad_s,
                              const std::vector<Complex>& response, double alpha,
                              const LevyOptions& options) {
  if (!std::isfinite(alpha) || !(alpha > 0) || !(alpha < 2)) {
    Throw("alpha must be in (0, 2) (got " + FormatDouble(alpha) + ")");
  }
  return FitG2(SelectBand(w_rad_s, response, options), alpha, options);
}

LinkIdentification IdentifyLinkModels(const std::vector<double>& w_rad_s,
                                      const std::vector<Complex>& response,
                                      const LevyOptions& options) {
  const BandData band = SelectBand(w_rad_s, response, options);
  LinkIdentification result;
  result.g1 = FitG1(band, options);
  // alpha = 1 + k delta strictly inside (1, 2).
  LinkModelFit best_stable, best_any;
  for (int k = 1;; ++k) {
    const double alpha = 1.0 + k * options.alpha_step;
    if (!(alpha < 2.0 - 1e-9)) break;
    const LinkModelFit fit = FitG2(band, alpha, options);
    ++result.g2_orders_tried;
    if (result.g2_orders_tried == 1 || fit.indices.levy_cost < best_any.indices.levy_cost) {
      best_any = fit;
    }
    if (fit.stable) {
      ++result.g2_orders_stable;
      if (result.g2_orders_stable == 1 ||
          fit.indices.levy_cost < best_stable.indices.levy_cost) {
        best_stable = fit;
      }
    }
  }
  result.g2 = result.g2_orders_stable > 0 ? best_stable : best_any;
  return result;
}

LinkIdentification IdentifyLinkModels(const FrequencyResponseEstimate& estimate,
                                      const LevyOptions& options) {
  return IdentifyLinkModels(estimate.w_rad_s, estimate.response, options);
}

FitIndices ComputeFitIndices(const std::vector<double>& w_rad_s,
                             const std::vector<Complex>& response, const IpmcLinkParams& params,
                             const LevyOptions& options) {
  return Indices(SelectBand(w_rad_s, response, options), params);
}

}  // namespace ipmc
