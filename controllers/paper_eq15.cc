#include "controllers/paper_eq15.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include <Eigen/Dense>

namespace ipmc {
namespace {

using Complex = std::complex<double>;
using Quartic = std::array<double, 5>;

constexpr int kDegree = 4;
// Newton steps that polish each companion-matrix root on the printed
// polynomial (the eigenvalues are already accurate to ~1e-13 relative).
constexpr int kPolishingSteps = 3;
// A root counts as real if its imaginary part is this small relative to
// its modulus.
constexpr double kRealRootTolerance = 1e-9;

Complex Horner(const Quartic& coefficients, Complex s) {
  Complex value = 0.0;
  for (double coefficient : coefficients) value = value * s + coefficient;
  return value;
}

double HornerDerivative(const Quartic& coefficients, double s) {
  double value = 0.0;
  for (int i = 0; i < kDegree; ++i) {
    value = value * s + coefficients[i] * (kDegree - i);
  }
  return value;
}

// The corners r_k > 0 of prod (s + r_k) = p(s) / p_0 (p's roots are -r_k),
// ascending; `which` names the polynomial in the error message.
std::vector<double> NegativeRealRootCorners(const Quartic& p, const char* which) {
  // Companion matrix of the monic s^4 + (p1/p0) s^3 + ... + p4/p0.
  Eigen::Matrix4d companion = Eigen::Matrix4d::Zero();
  for (int i = 0; i < kDegree; ++i) companion(0, i) = -p[i + 1] / p[0];
  for (int i = 1; i < kDegree; ++i) companion(i, i - 1) = 1.0;
  const Eigen::Vector4cd roots = Eigen::EigenSolver<Eigen::Matrix4d>(companion).eigenvalues();
  std::vector<double> corners;
  for (const Complex& root : roots) {
    if (std::abs(root.imag()) > kRealRootTolerance * std::abs(root) || !(root.real() < 0)) {
      char message[160];
      std::snprintf(message, sizeof(message),
                    "eq. 15: the %s has a root %.6g%+.6gi that is not real and negative", which,
                    root.real(), root.imag());
      throw std::logic_error(message);
    }
    double s = root.real();
    for (int step = 0; step < kPolishingSteps; ++step) {
      const double slope = HornerDerivative(p, s);
      if (slope == 0.0) break;
      s -= Horner(p, s).real() / slope;
    }
    corners.push_back(-s);
  }
  std::sort(corners.begin(), corners.end());
  return corners;
}

std::string PolynomialText(const Quartic& coefficients) {
  std::string text;
  for (int i = 0; i <= kDegree; ++i) {
    char term[48];
    const int power = kDegree - i;
    if (power > 1) {
      std::snprintf(term, sizeof(term), "%g s^%d", coefficients[i], power);
    } else if (power == 1) {
      std::snprintf(term, sizeof(term), "%g s", coefficients[i]);
    } else {
      std::snprintf(term, sizeof(term), "%g", coefficients[i]);
    }
    if (!text.empty()) text += " + ";
    text += term;
  }
  return text;
}

}  // namespace

Complex Eq15Evaluate(Complex s) { return Horner(kEq15Numerator, s) / Horner(kEq15Denominator, s); }

std::string Eq15Description() {
  return "C(s) = (" + PolynomialText(kEq15Numerator) + ") / (" + PolynomialText(kEq15Denominator) +
         ") (eq. 15)";
}

ZeroPoleGain Eq15ZeroPoleGain() {
  ZeroPoleGain zpk;
  zpk.zero_corners_rad_s = NegativeRealRootCorners(kEq15Numerator, "numerator");
  zpk.pole_corners_rad_s = NegativeRealRootCorners(kEq15Denominator, "denominator");
  zpk.gain = kEq15Numerator[0] / kEq15Denominator[0];
  return zpk;
}

StateSpace Eq15StateSpace() { return ZeroPoleGainStateSpace(Eq15ZeroPoleGain()); }

}  // namespace ipmc
