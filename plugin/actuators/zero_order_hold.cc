#include "plugin/actuators/zero_order_hold.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unsupported/Eigen/MatrixFunctions>
#include <utility>

namespace ipmc {

ZeroOrderHold::ZeroOrderHold(std::vector<Eigen::MatrixXd> a, std::vector<Eigen::VectorXd> b)
    : a_(std::move(a)), b_(std::move(b)) {
  if (a_.size() != b_.size()) {
    throw std::invalid_argument("zero-order hold: one B per A needed");
  }
  int offset = 0;
  Eigen::Index largest = 0;
  for (size_t q = 0; q < a_.size(); ++q) {
    if (a_[q].rows() != a_[q].cols() || b_[q].size() != a_[q].rows()) {
      throw std::invalid_argument("zero-order hold: block " + std::to_string(q + 1) +
                                  " needs a square A and a B of its size");
    }
    offset_.push_back(offset);
    offset += static_cast<int>(a_[q].rows());
    largest = std::max(largest, a_[q].rows());
  }
  work_.resize(largest);
}

double ZeroOrderHold::RoundedInterval_s(double h_s) {
  if (!(h_s > 0)) return 0.0;
  int exponent = 0;
  const double mantissa = std::frexp(h_s, &exponent);  // in [0.5, 1)
  return std::ldexp(std::round(std::ldexp(mantissa, kIntervalBits)), exponent - kIntervalBits);
}

const ZeroOrderHold::Interval& ZeroOrderHold::Matrices(double rounded_h_s) {
  for (const Interval& interval : cache_) {
    if (interval.h_s == rounded_h_s) return interval;
  }
  Interval interval;
  interval.h_s = rounded_h_s;
  for (size_t q = 0; q < a_.size(); ++q) {
    const Eigen::Index n = a_[q].rows();
    Eigen::MatrixXd augmented = Eigen::MatrixXd::Zero(n + 1, n + 1);
    augmented.topLeftCorner(n, n) = a_[q] * rounded_h_s;
    augmented.topRightCorner(n, 1) = b_[q] * rounded_h_s;
    const Eigen::MatrixXd exponential = augmented.exp();
    interval.phi.push_back(exponential.topLeftCorner(n, n));
    interval.gamma.push_back(exponential.topRightCorner(n, 1));
  }
  ++exponentials_;
  if (cache_.size() < kCacheSize) {
    cache_.push_back(std::move(interval));
    return cache_.back();
  }
  Interval& slot = cache_[next_slot_];
  next_slot_ = (next_slot_ + 1) % kCacheSize;
  slot = std::move(interval);
  return slot;
}

void ZeroOrderHold::Advance(double h_s, const std::vector<double>& u, Eigen::VectorXd* x) {
  if (!(h_s >= 0) || !std::isfinite(h_s)) {
    throw std::invalid_argument("zero-order hold: the interval must be finite and >= 0");
  }
  const double rounded_h_s = RoundedInterval_s(h_s);
  if (rounded_h_s == 0.0) return;
  const Interval& interval = Matrices(rounded_h_s);
  for (size_t q = 0; q < a_.size(); ++q) {
    const Eigen::Index n = a_[q].rows();
    auto state = x->segment(offset_[q], n);
    auto work = work_.head(n);
    work.noalias() = interval.phi[q] * state;
    state = work + interval.gamma[q] * u[q];
  }
  ++advances_;
}

}  // namespace ipmc
