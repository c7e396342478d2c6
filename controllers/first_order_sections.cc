#include "controllers/first_order_sections.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>

#include "sim/base/numbers.h"

namespace ipmc {
namespace {

using Complex = std::complex<double>;

// z - 1 on the unit circle at w T, without the cancellation of cos - 1:
// the poles near z = 1 are resolved to their own precision.
Complex UnitCircleMinusOne(double w_T) {
  const double half = std::sin(0.5 * w_T);
  return {-2.0 * half * half, std::sin(w_T)};
}

// The block's own transfer function c (z I - a)^-1 b + d, with z I - a as
// (z - 1) I + (I - a).
Complex BlockResponse(const DiscreteStateSpace& block, Complex z_minus_1) {
  const Eigen::Index n = block.a.rows();
  Complex value = block.d(0, 0);
  if (n == 0) return value;
  const Eigen::MatrixXd distance = Eigen::MatrixXd::Identity(n, n) - block.a;
  const Eigen::MatrixXcd shifted =
      z_minus_1 * Eigen::MatrixXcd::Identity(n, n) + distance.cast<Complex>();
  const Eigen::VectorXcd x = shifted.partialPivLu().solve(block.b.cast<Complex>());
  return value + (block.c.cast<Complex>() * x)(0, 0);
}

bool LowerTriangular(const Eigen::MatrixXd& a) {
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    for (Eigen::Index j = i + 1; j < a.cols(); ++j) {
      if (a(i, j) != 0) return false;
    }
  }
  return true;
}

// The poles and each one's residue (c v)(w b) / (w v), v and w its right
// and left eigenvectors. A lower-triangular a (a cascade of first-order
// blocks, as Oustaloup's realisation is) has its poles on the diagonal
// and its eigenvectors by substitution, exactly to the differences of
// its poles; any other goes through Eigen's EigenSolver.
struct Modes {
  std::vector<Complex> poles, residues;
};

Modes TriangularModes(const DiscreteStateSpace& block) {
  const Eigen::MatrixXd& a = block.a;
  const Eigen::Index n = a.rows();
  Modes modes;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double pole = a(j, j);
    // Right: (a - p I) v = 0 with v_j = 1, v_i = 0 above j.
    Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
    v(j) = 1.0;
    for (Eigen::Index i = j + 1; i < n; ++i) {
      double sum = 0;
      for (Eigen::Index k = j; k < i; ++k) sum += a(i, k) * v(k);
      const double gap = pole - a(i, i);
      if (gap == 0) throw std::invalid_argument("repeated pole " + FormatDouble(pole));
      v(i) = sum / gap;
    }
    // Left: w (a - p I) = 0 with w_j = 1, w_i = 0 below j.
    Eigen::RowVectorXd w = Eigen::RowVectorXd::Zero(n);
    w(j) = 1.0;
    for (Eigen::Index i = j; i-- > 0;) {
      double sum = 0;
      for (Eigen::Index k = i + 1; k <= j; ++k) sum += w(k) * a(k, i);
      w(i) = sum / (pole - a(i, i));
    }
    modes.poles.push_back(pole);
    modes.residues.push_back((block.c.row(0).dot(v)) * (w.dot(block.b.col(0))) / w.dot(v));
  }
  return modes;
}

Modes GeneralModes(const DiscreteStateSpace& block) {
  const Eigen::EigenSolver<Eigen::MatrixXd> solver(block.a);
  if (solver.info() != Eigen::Success) {
    throw std::invalid_argument("the eigenvalues did not converge");
  }
  const Eigen::MatrixXcd v = solver.eigenvectors();
  const Eigen::VectorXcd input = v.partialPivLu().solve(block.b.col(0).cast<Complex>());
  const Eigen::RowVectorXcd output = block.c.cast<Complex>() * v;
  Modes modes;
  for (Eigen::Index i = 0; i < v.cols(); ++i) {
    modes.poles.push_back(solver.eigenvalues()(i));
    modes.residues.push_back(output(i) * input(i));
  }
  return modes;
}

// Relative tolerance of the decomposition's check, and the check's grid.
constexpr double kCheckTolerance = 1e-9;
constexpr int kCheckPoints = 60;
constexpr double kCheckLowRadS = 1e-6;

}  // namespace

double FirstOrderSection::CornerRadS(double sample_period_s) const {
  return alpha == 0 ? 0.0 : -std::log1p(-alpha) / sample_period_s;
}

Complex ParallelSections::Evaluate(Complex z) const {
  Complex value = d;
  for (const FirstOrderSection& s : sections) value += s.c * s.b / (z - s.pole());
  return value;
}

ParallelSections ParallelFirstOrderSections(const DiscreteStateSpace& block) {
  ParallelSections result;
  result.d = block.d(0, 0);
  result.sample_period_s = block.sample_period_s;
  const Eigen::Index n = block.a.rows();
  if (n == 0) return result;
  Modes modes;
  try {
    modes = LowerTriangular(block.a) ? TriangularModes(block) : GeneralModes(block);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(std::string("ParallelFirstOrderSections: ") + error.what() +
                                ": no first-order sections");
  }
  for (size_t i = 0; i < modes.poles.size(); ++i) {
    const Complex pole = modes.poles[i];
    if (pole.imag() != 0 || !(pole.real() > -1) || pole.real() > 1) {
      throw std::invalid_argument("ParallelFirstOrderSections: pole " + FormatDouble(pole.real()) +
                                  " + " + FormatDouble(pole.imag()) +
                                  "j is not real and in (-1, 1]: no first-order sections");
    }
    FirstOrderSection section;
    // 1 - p is exact in double for p in [0.5, 1] (Sterbenz).
    section.alpha = 1.0 - pole.real();
    section.b = section.alpha > 0 ? section.alpha : 1.0;
    section.c = modes.residues[i].real() / section.b;
    result.sections.push_back(section);
  }
  std::sort(result.sections.begin(), result.sections.end(),
            [](const FirstOrderSection& x, const FirstOrderSection& y) { return x.alpha < y.alpha; });
  for (size_t i = 1; i < result.sections.size(); ++i) {
    if (result.sections[i].alpha == result.sections[i - 1].alpha) {
      throw std::invalid_argument("ParallelFirstOrderSections: repeated pole " +
                                  FormatDouble(result.sections[i].pole()) +
                                  ": no first-order sections");
    }
  }
  const double period = block.sample_period_s;
  for (int k = 0; k < kCheckPoints; ++k) {
    const double w = kCheckLowRadS * std::pow(kPi / period / kCheckLowRadS,
                                              static_cast<double>(k) / (kCheckPoints - 1));
    const Complex z_minus_1 = UnitCircleMinusOne(w * period);
    const Complex expected = BlockResponse(block, z_minus_1);
    Complex got = result.d;
    for (const FirstOrderSection& s : result.sections) got += s.c * s.b / (z_minus_1 + s.alpha);
    if (!(std::abs(got - expected) <= kCheckTolerance * std::abs(expected))) {
      throw std::invalid_argument(
          "ParallelFirstOrderSections: the sections depart from the block by " +
          FormatDouble(std::abs(got - expected) / std::abs(expected), 3) + " (relative) at " +
          FormatDouble(w, 4) + " rad/s: the poles are too close for a modal decomposition");
    }
  }
  return result;
}

}  // namespace ipmc
