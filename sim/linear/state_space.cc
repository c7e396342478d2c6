#include "sim/linear/state_space.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include <Eigen/LU>

namespace ipmc {
namespace {

std::string SizeString(const Eigen::MatrixXd& m) {
  std::ostringstream out;
  out << m.rows() << "x" << m.cols();
  return out.str();
}

void RequireSize(const char* what, const char* name, const Eigen::MatrixXd& m,
                 Eigen::Index rows, Eigen::Index cols) {
  if (m.rows() != rows || m.cols() != cols) {
    std::ostringstream out;
    out << what << ": " << name << " must be " << rows << "x" << cols
        << " (got " << SizeString(m) << ")";
    throw std::invalid_argument(out.str());
  }
  if (!m.allFinite()) {
    throw std::invalid_argument(std::string(what) + ": " + name +
                                " must have finite entries");
  }
}

}  // namespace

int StateSpace::States() const { return static_cast<int>(a.rows()); }

void StateSpace::Validate(const char* what) const {
  const Eigen::Index n = a.rows();
  RequireSize(what, "a", a, n, n);
  RequireSize(what, "b", b, n, 1);
  RequireSize(what, "c", c, 1, n);
  RequireSize(what, "d", d, 1, 1);
}

std::complex<double> StateSpace::Evaluate(std::complex<double> s) const {
  Validate("StateSpace::Evaluate");
  const std::complex<double> direct = d(0, 0);
  if (States() == 0) return direct;
  const Eigen::Index n = a.rows();
  Eigen::MatrixXcd resolvent =
      s * Eigen::MatrixXcd::Identity(n, n) - a.cast<std::complex<double>>();
  const Eigen::VectorXcd x =
      resolvent.partialPivLu().solve(b.cast<std::complex<double>>());
  return (c.cast<std::complex<double>>() * x)(0, 0) + direct;
}

StateSpace Series(const StateSpace& first, const StateSpace& second) {
  first.Validate("Series: first");
  second.Validate("Series: second");
  const Eigen::Index n1 = first.a.rows();
  const Eigen::Index n2 = second.a.rows();
  StateSpace out;
  out.a = Eigen::MatrixXd::Zero(n1 + n2, n1 + n2);
  out.a.topLeftCorner(n1, n1) = first.a;
  out.a.bottomLeftCorner(n2, n1) = second.b * first.c;
  out.a.bottomRightCorner(n2, n2) = second.a;
  out.b = Eigen::MatrixXd(n1 + n2, 1);
  out.b.topRows(n1) = first.b;
  out.b.bottomRows(n2) = second.b * first.d;
  out.c = Eigen::MatrixXd(1, n1 + n2);
  out.c.leftCols(n1) = second.d * first.c;
  out.c.rightCols(n2) = second.c;
  out.d = second.d * first.d;
  return out;
}

StateSpace Feedback(const StateSpace& forward, const StateSpace& back,
                    double sign) {
  forward.Validate("Feedback: forward");
  back.Validate("Feedback: back");
  if (sign != 1.0 && sign != -1.0) {
    std::ostringstream out;
    out << "Feedback: sign must be -1 or +1 (got " << sign << ")";
    throw std::invalid_argument(out.str());
  }
  const double df = forward.d(0, 0);
  const double db = back.d(0, 0);
  const double e = 1.0 - sign * df * db;
  // Ill-posed (algebraic loop with unit loop gain) when e vanishes.
  if (std::abs(e) <= 1e-12 * (1.0 + std::abs(df * db))) {
    std::ostringstream out;
    out << "Feedback: loop is not well-posed, 1 - sign*d_forward*d_back = "
        << e << " (d_forward = " << df << ", d_back = " << db << ")";
    throw std::invalid_argument(out.str());
  }
  const Eigen::Index nf = forward.a.rows();
  const Eigen::Index nb = back.a.rows();
  // y = cy_f x_f + cy_b x_b + dy r
  const Eigen::MatrixXd cy_f = forward.c / e;
  const Eigen::MatrixXd cy_b = (sign * df / e) * back.c;
  const double dy = df / e;
  // u_f = r + sign (c_b x_b + d_b y)
  const Eigen::MatrixXd cu_f = sign * db * cy_f;
  const Eigen::MatrixXd cu_b = sign * (back.c + db * cy_b);
  const double du = 1.0 + sign * db * dy;

  StateSpace out;
  out.a = Eigen::MatrixXd::Zero(nf + nb, nf + nb);
  out.a.topLeftCorner(nf, nf) = forward.a + forward.b * cu_f;
  out.a.topRightCorner(nf, nb) = forward.b * cu_b;
  out.a.bottomLeftCorner(nb, nf) = back.b * cy_f;
  out.a.bottomRightCorner(nb, nb) = back.a + back.b * cy_b;
  out.b = Eigen::MatrixXd(nf + nb, 1);
  out.b.topRows(nf) = forward.b * du;
  out.b.bottomRows(nb) = back.b * dy;
  out.c = Eigen::MatrixXd(1, nf + nb);
  out.c.leftCols(nf) = cy_f;
  out.c.rightCols(nb) = cy_b;
  out.d = Eigen::MatrixXd::Constant(1, 1, dy);
  return out;
}

StateSpace Gain(double k) {
  if (!std::isfinite(k)) {
    throw std::invalid_argument("Gain: k must be finite");
  }
  StateSpace out;
  out.a = Eigen::MatrixXd(0, 0);
  out.b = Eigen::MatrixXd(0, 1);
  out.c = Eigen::MatrixXd(1, 0);
  out.d = Eigen::MatrixXd::Constant(1, 1, k);
  return out;
}

StateSpace SecondOrderLag(double a0, double b1, double b2) {
  if (!std::isfinite(a0)) {
    throw std::invalid_argument("SecondOrderLag: a0 must be finite");
  }
  if (!std::isfinite(b2) || b2 < 0) {
    std::ostringstream out;
    out << "SecondOrderLag: b2 must be finite and >= 0 (got " << b2 << ")";
    throw std::invalid_argument(out.str());
  }
  const bool b1_ok = std::isfinite(b1) && (b2 > 0 ? b1 >= 0 : b1 > 0);
  if (!b1_ok) {
    std::ostringstream out;
    out << "SecondOrderLag: b1 must be finite and " << (b2 > 0 ? ">= 0" : "> 0")
        << " (got " << b1 << ")";
    throw std::invalid_argument(out.str());
  }
  StateSpace out;
  if (b2 == 0) {
    // b1 y' + y = a0 u
    out.a = Eigen::MatrixXd::Constant(1, 1, -1.0 / b1);
    out.b = Eigen::MatrixXd::Constant(1, 1, a0 / b1);
    out.c = Eigen::MatrixXd::Constant(1, 1, 1.0);
    out.d = Eigen::MatrixXd::Zero(1, 1);
    return out;
  }
  // b2 y'' + b1 y' + y = a0 u, x = [y, y'].
  out.a = Eigen::MatrixXd(2, 2);
  out.a << 0.0, 1.0, -1.0 / b2, -b1 / b2;
  out.b = Eigen::MatrixXd(2, 1);
  out.b << 0.0, a0 / b2;
  out.c = Eigen::MatrixXd(1, 2);
  out.c << 1.0, 0.0;
  out.d = Eigen::MatrixXd::Zero(1, 1);
  return out;
}

StateSpace Integrators(int k) {
  if (k < 1) {
    std::ostringstream out;
    out << "Integrators: k must be >= 1 (got " << k << ")";
    throw std::invalid_argument(out.str());
  }
  // x_1' = u, x_i' = x_(i-1), y = x_k.
  StateSpace out;
  out.a = Eigen::MatrixXd::Zero(k, k);
  for (int i = 1; i < k; ++i) out.a(i, i - 1) = 1.0;
  out.b = Eigen::MatrixXd::Zero(k, 1);
  out.b(0, 0) = 1.0;
  out.c = Eigen::MatrixXd::Zero(1, k);
  out.c(0, k - 1) = 1.0;
  out.d = Eigen::MatrixXd::Zero(1, 1);
  return out;
}

}  // namespace ipmc
