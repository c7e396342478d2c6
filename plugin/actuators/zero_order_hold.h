// Exact integration of the IPMC links' linear ODE under a zero-order hold.
//
// The stacked link models (plugin/actuators/stacked_linear_system.h) are
// linear and time-invariant, dx/dt = A x + B u, and the coupling holds each
// link's voltage u_q constant between the controller's samples. Over an
// interval of length h with u held, the solution is exact in closed form
// (e.g. G. F. Franklin, J. D. Powell, M. L. Workman, "Digital Control of
// Dynamic Systems", 3rd ed., 1998, section 4.3.3):
//
//   x(t + h) = Phi(h) x(t) + Gamma(h) u,
//   Phi(h) = e^(A h),  Gamma(h) = int_0^h e^(A s) ds B,
//
// both read off one matrix exponential of the augmented block
// [A B; 0 0] h = [Phi Gamma; 0 1] (Van Loan, "Computing integrals
// involving the matrix exponential", IEEE TAC 23(3), 1978), computed per
// link block by Eigen's scaling-and-squaring Pade approximant. An advance
// costs one product of each block's Phi with its state: no error control,
// no internal steps, no restarts at the voltage changes.
//
// The matrices depend on h alone. They are kept for the few interval
// lengths a run uses (its time step, the controller's sample), found by
// h rounded to kIntervalBits significant bits; the rounding moves h by at
// most 2^-kIntervalBits of itself (1e-15 s at 1 ms), far below the
// integration errors of CVODE at any tolerance it allows, and makes the
// result a function of (x, u, h) alone, whatever intervals came before.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace ipmc {

class ZeroOrderHold {
 public:
  // One block per link: its A (square) and B (one column), stacked in order
  // in the state. Throws std::invalid_argument on mismatched sizes.
  ZeroOrderHold(std::vector<Eigen::MatrixXd> a, std::vector<Eigen::VectorXd> b);

  // x <- Phi(h) x + Gamma(h) u over every block, u one voltage per block.
  // h >= 0 and finite (h = 0 leaves x unchanged).
  void Advance(double h_s, const std::vector<double>& u, Eigen::VectorXd* x);

  // Advances made, and matrix exponentials computed (one per interval
  // length seen, up to the cache's size).
  long Advances() const { return advances_; }
  long Exponentials() const { return exponentials_; }

  // h rounded to kIntervalBits significant bits (the key of the matrices).
  static double RoundedInterval_s(double h_s);
  static constexpr int kIntervalBits = 40;

 private:
  struct Interval {
    double h_s = 0;
    std::vector<Eigen::MatrixXd> phi;
    std::vector<Eigen::VectorXd> gamma;
  };
  const Interval& Matrices(double rounded_h_s);

  std::vector<Eigen::MatrixXd> a_;
  std::vector<Eigen::VectorXd> b_;
  std::vector<int> offset_;
  std::vector<Interval> cache_;  // at most kCacheSize, the newest replacing the oldest
  size_t next_slot_ = 0;
  Eigen::VectorXd work_;
  long advances_ = 0, exponentials_ = 0;
  static constexpr size_t kCacheSize = 4;
};

}  // namespace ipmc
