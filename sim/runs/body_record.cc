#include "sim/runs/body_record.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/io/columns.h"

namespace ipmc {
namespace {

// A gait's ideal body: segment k keeps the realised body's mean length
// from point k-1 to tip k and turns from segment k-1 (the head's axis for
// k = 1) by the reference angle of joint k, the hinge at its root; joints
// without a reference column stay straight.
std::vector<std::vector<BodyPoint>> GaitIdeal(const CsvTable& table,
                                              const std::vector<std::vector<BodyPoint>>& realised) {
  const size_t samples = realised.size();
  const size_t tips = realised.front().size() - 1;
  std::vector<double> segment_mm(tips, 0.0);
  std::vector<std::vector<double>> reference(tips);
  for (size_t k = 0; k < tips; ++k) {
    const int joint = static_cast<int>(k) + 1;
    if (table.Has(columns::JointReference(joint))) {
      reference[k] = table.Numbers(columns::JointReference(joint));
    }
    for (size_t i = 0; i < samples; ++i) {
      const std::vector<BodyPoint>& p = realised[i];
      segment_mm[k] += std::hypot(p[k + 1].x - p[k].x, p[k + 1].y - p[k].y) / samples;
    }
  }
  std::vector<std::vector<BodyPoint>> ideal(samples);
  for (size_t i = 0; i < samples; ++i) {
    BodyPoint point;
    double direction = 0.0;
    ideal[i].push_back(point);
    for (size_t k = 0; k < tips; ++k) {
      if (!reference[k].empty()) direction += reference[k][i];
      point.x += segment_mm[k] * std::cos(direction);
      point.y += segment_mm[k] * std::sin(direction);
      ideal[i].push_back(point);
    }
  }
  return ideal;
}

}  // namespace

BodyRecord ReadBodyRecord(const CsvTable& table) {
  if (table.Rows() < 1) {
    throw InputError(InputProblem::kMissing, {table.source()}, "",
                     "needs at least 1 data rows, has 0");
  }
  BodyRecord body;
  body.t_s = table.Numbers(columns::kTime);
  const std::vector<double> head_x = table.Numbers(columns::kHeadX);
  const std::vector<double> head_y = table.Numbers(columns::kHeadY);
  const std::vector<double> yaw = table.Numbers(columns::kYaw);
  std::vector<std::vector<double>> tip_x, tip_y;
  for (int k = 1; k == 1 || table.Has(columns::TipX(k)); ++k) {
    tip_x.push_back(table.Numbers(columns::TipX(k)));
    tip_y.push_back(table.Numbers(columns::TipY(k)));
  }
  const size_t samples = body.t_s.size();
  const size_t tips = tip_x.size();
  body.realised.resize(samples);
  for (size_t i = 0; i < samples; ++i) {
    const double c = std::cos(yaw[i]), s = std::sin(yaw[i]);
    body.realised[i].push_back({0.0, 0.0});
    for (size_t k = 0; k < tips; ++k) {
      const double dx = tip_x[k][i] - head_x[i], dy = tip_y[k][i] - head_y[i];
      body.realised[i].push_back({c * dx + s * dy, -s * dx + c * dy});
    }
  }
  if (!table.Has(columns::Reference(1))) {
    if (table.Has(columns::JointReference(1))) body.ideal = GaitIdeal(table, body.realised);
    return body;
  }

  // Per segment k (point k-1 to tip k): mean length, and the length L_k
  // that maps the measured deflection onto the realised turn angle.
  std::vector<double> segment_mm(tips, 0.0), link_mm(tips, 0.0);
  std::vector<std::vector<double>> reference(tips);
  for (size_t k = 0; k < tips; ++k) {
    const int link = static_cast<int>(k) + 1;
    double numerator = 0.0, denominator = 0.0;
    const bool referenced = table.Has(columns::Reference(link));
    std::vector<double> measured;
    if (referenced) {
      reference[k] = table.Numbers(columns::Reference(link));
      measured = table.Numbers(columns::Measured(link));
    }
    for (size_t i = 0; i < samples; ++i) {
      const std::vector<BodyPoint>& p = body.realised[i];
      segment_mm[k] += std::hypot(p[k + 1].x - p[k].x, p[k + 1].y - p[k].y) / samples;
      if (!referenced) continue;
      const double direction = std::atan2(p[k + 1].y - p[k].y, p[k + 1].x - p[k].x);
      const double previous = k == 0 ? 0.0 : std::atan2(p[k].y - p[k - 1].y, p[k].x - p[k - 1].x);
      const double sine = std::sin(std::remainder(direction - previous, kTwoPi));
      numerator += measured[i] * sine;
      denominator += sine * sine;
    }
    const double fitted = denominator > 0.0 ? numerator / denominator : 0.0;
    link_mm[k] = std::isfinite(fitted) && fitted > 0.0 ? fitted : segment_mm[k];
  }
  body.ideal.resize(samples);
  for (size_t i = 0; i < samples; ++i) {
    BodyPoint point;
    double direction = 0.0;
    body.ideal[i].push_back(point);
    for (size_t k = 0; k < tips; ++k) {
      if (!reference[k].empty()) {
        direction += std::asin(std::clamp(reference[k][i] / link_mm[k], -1.0, 1.0));
      }
      point.x += segment_mm[k] * std::cos(direction);
      point.y += segment_mm[k] * std::sin(direction);
      body.ideal[i].push_back(point);
    }
  }
  return body;
}

}  // namespace ipmc
