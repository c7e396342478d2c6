// The IPMC links of a flagellum as one stacked linear system, fixed by the
// model.
//
// Each link q is a SISO state-space block (sim/linear/ipmc_link_model.h), voltage
// u_q [V] -> free tip deflection y_q [mm]. The blocks are stacked into the
// augmented Oustaloup state x = [x_1; ...; x_L] with block-diagonal A:
//
//   dx/dt = A x + B u,   y_q = c_q x_q + d_q u_q.
//
// Built once from the blocks and never changed; the integrators
// (plugin/actuators/linear_system_integrator.h) read it.
#pragma once

#include <vector>

#include <Eigen/Dense>

#include "sim/linear/state_space.h"

namespace ipmc {

// One link's block of the stacked system.
struct LinkBlock {
  int first_state = 0;  // index of its first state in x
  int size = 0;         // its number of states
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
  Eigen::RowVectorXd c;
  double d = 0;
};

class StackedLinearSystem {
 public:
  // One SISO block per link. Throws std::invalid_argument with no block,
  // on a malformed block (naming the link) or with no state in total.
  explicit StackedLinearSystem(const std::vector<StateSpace>& blocks);

  int Links() const { return static_cast<int>(blocks_.size()); }
  int States() const { return states_; }
  const std::vector<LinkBlock>& Blocks() const { return blocks_; }

  // The block-diagonal A, column-major like SUNDIALS' matrices, and the
  // widest reach of its nonzeros below and above the diagonal.
  const Eigen::MatrixXd& StackedA() const { return stacked_a_; }
  int LowerBandwidth() const { return lower_bandwidth_; }
  int UpperBandwidth() const { return upper_bandwidth_; }

  // out = A in + add (add may be null), States() values each.
  void ApplyA(const double* in, const double* add, double* out) const;

  // y_q = c_q x_q + d_q u_q [mm] of link q (0-based) for the stacked x.
  double Output(int link, const Eigen::VectorXd& x, double u_V) const;

 private:
  std::vector<LinkBlock> blocks_;
  int states_ = 0;
  Eigen::MatrixXd stacked_a_;
  int lower_bandwidth_ = 0;
  int upper_bandwidth_ = 0;
  // A by rows for ApplyA: row i holds its entries from column
  // row_first_column_[i] to its last nonzero, stored one after the other
  // from row_values_[row_start_[i]] (the cascades' A is lower triangular,
  // so a row is a run of columns with few zeros in it).
  std::vector<int> row_start_, row_first_column_;
  std::vector<double> row_values_;
};

}  // namespace ipmc
