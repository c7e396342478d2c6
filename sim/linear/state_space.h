// Small single-input single-output (SISO) linear state-space systems.
//
//   dx/dt = a x + b u,   y = c x + d u
//
// with a (n x n), b (n x 1), c (1 x n), d (1 x 1). A system with n = 0 is a
// static gain. Blocks are composed in state space (Series, Feedback) rather
// than by multiplying polynomials, so that realisations spanning many
// decades of frequency (Oustaloup approximations) stay well conditioned.
#ifndef IPMC_SWIM_CONTROLLERS_STATE_SPACE_H_
#define IPMC_SWIM_CONTROLLERS_STATE_SPACE_H_

#include <complex>

#include <Eigen/Dense>

namespace ipmc {

struct StateSpace {
  Eigen::MatrixXd a;  // n x n
  Eigen::MatrixXd b;  // n x 1
  Eigen::MatrixXd c;  // 1 x n
  Eigen::MatrixXd d;  // 1 x 1

  // Number of states n.
  int States() const;

  // Transfer function H(s) = c (s I - a)^-1 b + d, by an LU solve of
  // (s I - a) (no polynomial expansion). Throws std::invalid_argument if
  // the matrices are not a SISO system of consistent sizes.
  std::complex<double> Evaluate(std::complex<double> s) const;

  // Throws std::invalid_argument naming the matrix whose size is wrong or
  // whose entries are not finite. `what` prefixes the message.
  void Validate(const char* what = "state space") const;
};

// second(first(u)): x = [x_first; x_second],
//   a = [a1 0; b2 c1 a2], b = [b1; b2 d1], c = [d2 c1, c2], d = d2 d1.
StateSpace Series(const StateSpace& first, const StateSpace& second);

// Closed loop y = forward(r + sign * back(y)); sign = -1 is negative
// feedback. With e = 1 - sign d_f d_b (must be nonzero: well-posed loop),
//   y = (c_f x_f + sign d_f c_b x_b + d_f r) / e,
//   u_f = r + sign (c_b x_b + d_b y),  u_b = y.
// Throws std::invalid_argument if the loop is not well-posed or sign is
// not +-1.
StateSpace Feedback(const StateSpace& forward, const StateSpace& back,
                    double sign = -1);

// Static gain y = k u (no states).
StateSpace Gain(double k);

// a0 / (b2 s^2 + b1 s + 1) in physical coordinates x = [y, dy/dt]:
//   b2 y'' + b1 y' + y = a0 u.
// b2 = 0 gives the first-order lag a0 / (b1 s + 1) with x = [y].
// Requires b2 >= 0, b1 > 0 (b1 >= 0 if b2 > 0), all finite; throws
// std::invalid_argument otherwise.
StateSpace SecondOrderLag(double a0, double b1, double b2);

// k integrators in series, y = u / s^k (k >= 1); x_i is the i-th integral.
StateSpace Integrators(int k);

}  // namespace ipmc

#endif  // IPMC_SWIM_CONTROLLERS_STATE_SPACE_H_
