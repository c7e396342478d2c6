#include "plugin/actuators/stacked_linear_system.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace ipmc {

StackedLinearSystem::StackedLinearSystem(const std::vector<StateSpace>& blocks) {
  if (blocks.empty()) {
    throw std::invalid_argument("ipmc actuator: needs at least one link");
  }
  for (std::size_t q = 0; q < blocks.size(); ++q) {
    const std::string what = "ipmc actuator: link " + std::to_string(q + 1);
    blocks[q].Validate(what.c_str());
    LinkBlock block;
    block.first_state = states_;
    block.size = blocks[q].States();
    block.a = blocks[q].a;
    block.b = blocks[q].b.col(0);
    block.c = blocks[q].c.row(0);
    block.d = blocks[q].d(0, 0);
    states_ += block.size;
    blocks_.push_back(std::move(block));
  }
  if (states_ == 0) {
    throw std::invalid_argument("ipmc actuator: the links have no states");
  }
  const int n = states_;
  stacked_a_ = Eigen::MatrixXd::Zero(n, n);
  for (const LinkBlock& block : blocks_) {
    stacked_a_.block(block.first_state, block.first_state, block.size, block.size) = block.a;
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (stacked_a_(i, j) == 0) continue;
      lower_bandwidth_ = std::max(lower_bandwidth_, i - j);
      upper_bandwidth_ = std::max(upper_bandwidth_, j - i);
    }
  }
  row_start_.push_back(0);
  for (int i = 0; i < n; ++i) {
    int first = n, last = -1;
    for (int j = 0; j < n; ++j) {
      if (stacked_a_(i, j) == 0) continue;
      first = std::min(first, j);
      last = j;
    }
    if (last < 0) first = last = 0;  // an empty row: one zero entry
    row_first_column_.push_back(first);
    for (int j = first; j <= last; ++j) row_values_.push_back(stacked_a_(i, j));
    row_start_.push_back(static_cast<int>(row_values_.size()));
  }
}

void StackedLinearSystem::ApplyA(const double* in, const double* add, double* out) const {
  const double* value = row_values_.data();
  for (int i = 0; i < states_; ++i) {
    const double* row = value + row_start_[i];
    const double* x = in + row_first_column_[i];
    const int count = row_start_[i + 1] - row_start_[i];
    double sum = add ? add[i] : 0.0;
    for (int k = 0; k < count; ++k) sum += row[k] * x[k];
    out[i] = sum;
  }
}

double StackedLinearSystem::Output(int link, const Eigen::VectorXd& x, double u_V) const {
  const LinkBlock& block = blocks_.at(link);
  return block.c.dot(x.segment(block.first_state, block.size)) + block.d * u_V;
}

}  // namespace ipmc
