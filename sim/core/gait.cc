#include "sim/core/gait.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/base/error.h"
#include "sim/io/files.h"
#include "sim/base/numbers.h"

namespace ipmc {
namespace {

void RequirePositiveFrequency(double frequency_Hz) {
  if (!(frequency_Hz > 0.0) || !std::isfinite(frequency_Hz)) {
    throw FieldError("gait: frequency_Hz must be finite and > 0 (got " + FormatShortest(frequency_Hz) +
                         ")",
                     "frequency_Hz", "finite and > 0");
  }
}

class SineGait final : public Gait {
 public:
  explicit SineGait(SineGaitConfig config) : config_(std::move(config)) {}
  int Joints() const override { return static_cast<int>(config_.amplitude_rad.size()); }
  double Period_s() const override { return 1.0 / config_.frequency_Hz; }
  JointReference At(double t_s) const override {
    const double w = kTwoPi * config_.frequency_Hz;
    JointReference ref;
    for (int j = 0; j < Joints(); ++j) {
      const double phase = w * t_s + config_.phase_rad[j];
      ref.angle_rad.push_back(config_.amplitude_rad[j] * std::sin(phase));
      ref.velocity_rad_s.push_back(config_.amplitude_rad[j] * w * std::cos(phase));
    }
    return ref;
  }
  std::string Describe() const override {
    std::ostringstream out;
    out << "sine gait, f = " << config_.frequency_Hz << " Hz";
    return out.str();
  }

 private:
  SineGaitConfig config_;
};

// Periodic square wave of unit amplitude with half-cosine ramps; phase p
// in cycles. Rise over [0, 1/4), hold +1, fall over [1/2, 3/4), hold -1.
void SmoothSquare(double p, double* value, double* slope_per_cycle) {
  p -= std::floor(p);
  constexpr double kRamp = 0.25;
  if (p < kRamp) {
    *value = -std::cos(kPi * p / kRamp);
    *slope_per_cycle = kPi / kRamp * std::sin(kPi * p / kRamp);
  } else if (p < 0.5) {
    *value = 1.0;
    *slope_per_cycle = 0.0;
  } else if (p < 0.5 + kRamp) {
    *value = std::cos(kPi * (p - 0.5) / kRamp);
    *slope_per_cycle = -kPi / kRamp * std::sin(kPi * (p - 0.5) / kRamp);
  } else {
    *value = -1.0;
    *slope_per_cycle = 0.0;
  }
}

class SquareStroke final : public Gait {
 public:
  explicit SquareStroke(SquareStrokeConfig config) : config_(config) {}
  int Joints() const override { return config_.joints; }
  double Period_s() const override { return 1.0 / config_.frequency_Hz; }
  JointReference At(double t_s) const override {
    JointReference ref;
    for (int j = 0; j < config_.joints; ++j) {
      double value = 0.0, slope = 0.0;
      SmoothSquare(t_s * config_.frequency_Hz - 0.25 * j, &value, &slope);
      ref.angle_rad.push_back(config_.amplitude_rad * value);
      ref.velocity_rad_s.push_back(config_.amplitude_rad * slope * config_.frequency_Hz);
    }
    return ref;
  }
  std::string Describe() const override {
    std::ostringstream out;
    out << "square stroke, f = " << config_.frequency_Hz << " Hz, A = " << config_.amplitude_rad
        << " rad";
    return out.str();
  }

 private:
  SquareStrokeConfig config_;
};

class CsvGait final : public Gait {
 public:
  CsvGait(std::string path, std::vector<double> times, std::vector<std::vector<double>> angles)
      : path_(std::move(path)), times_(std::move(times)), angles_(std::move(angles)) {}
  int Joints() const override { return static_cast<int>(angles_.front().size()); }
  double Period_s() const override { return times_.back() - times_.front(); }
  JointReference At(double t_s) const override {
    double local = std::fmod(t_s - times_.front(), Period_s());
    if (local < 0) local += Period_s();
    local += times_.front();
    const size_t hi = std::min<size_t>(
        times_.size() - 1,
        std::max<size_t>(1, std::upper_bound(times_.begin(), times_.end(), local) - times_.begin()));
    const size_t lo = hi - 1;
    const double span = times_[hi] - times_[lo];
    const double frac = (local - times_[lo]) / span;
    JointReference ref;
    for (int j = 0; j < Joints(); ++j) {
      const double a = angles_[lo][j], b = angles_[hi][j];
      ref.angle_rad.push_back(a + frac * (b - a));
      ref.velocity_rad_s.push_back((b - a) / span);
    }
    return ref;
  }
  std::string Describe() const override { return "CSV gait " + path_; }

 private:
  std::string path_;
  std::vector<double> times_;
  std::vector<std::vector<double>> angles_;
};

}  // namespace

void SineGaitConfig::Validate() const {
  RequirePositiveFrequency(frequency_Hz);
  if (amplitude_rad.empty()) {
    throw FieldError("gait: amplitude_rad is empty (one value per driven joint)", "amplitude_rad",
                     "one value per driven joint");
  }
  if (phase_rad.size() != amplitude_rad.size()) {
    throw FieldError("gait: phase_rad has " + std::to_string(phase_rad.size()) +
                         " values, amplitude_rad has " + std::to_string(amplitude_rad.size()),
                     "phase_rad", std::to_string(amplitude_rad.size()) + " values");
  }
  for (double a : amplitude_rad) {
    if (!std::isfinite(a) || std::abs(a) > kPi) {
      throw FieldError("gait: amplitude_rad must be finite and in [-pi, pi] (got " +
                           FormatShortest(a) + ")",
                       "amplitude_rad", "finite, in [-pi, pi]");
    }
  }
  for (double p : phase_rad) {
    if (!std::isfinite(p)) {
      throw FieldError("gait: phase_rad must be finite (got " + FormatShortest(p) + ")",
                       "phase_rad", "finite");
    }
  }
}

std::unique_ptr<Gait> MakeSineGait(const SineGaitConfig& config) {
  config.Validate();
  return std::make_unique<SineGait>(config);
}

SineGaitConfig TravellingWave(int joints, double frequency_Hz, double amplitude_rad,
                              double phase_lag_rad) {
  SineGaitConfig config;
  config.frequency_Hz = frequency_Hz;
  for (int j = 0; j < joints; ++j) {
    config.amplitude_rad.push_back(amplitude_rad);
    config.phase_rad.push_back(-j * phase_lag_rad);
  }
  return config;
}

void SquareStrokeConfig::Validate() const {
  RequirePositiveFrequency(frequency_Hz);
  if (!(amplitude_rad > 0.0) || amplitude_rad > kPi) {
    throw FieldError("gait: square stroke amplitude_rad must be in (0, pi] (got " +
                         FormatShortest(amplitude_rad) + ")",
                     "amplitude_rad", "(0, pi]");
  }
  if (joints < 1) {
    throw FieldError("gait: square stroke needs joints >= 1 (got " + std::to_string(joints) +
                         "; the model's servo_* actuators)",
                     "joints", ">= 1");
  }
}

std::unique_ptr<Gait> MakeSquareStroke(const SquareStrokeConfig& config) {
  config.Validate();
  return std::make_unique<SquareStroke>(config);
}

std::unique_ptr<Gait> LoadCsvGait(const std::string& path, int joints) {
  std::vector<double> times;
  std::vector<std::vector<double>> angles;
  for (const CsvRecord& record : ParseCsvRecords(ReadTextFile(path, "gait CSV"), path)) {
    const InputLocation where{path, static_cast<std::uint32_t>(record.line)};
    std::vector<double> values;
    for (const std::string& field : record.fields) {
      const std::optional<double> value = ParseDouble(field);
      if (!value || !std::isfinite(*value)) break;
      values.push_back(*value);
    }
    if (values.size() != record.fields.size()) {
      if (times.empty() && record.line == 1) continue;  // header
      throw InputError(InputProblem::kBadValue, where, "", "non-numeric or non-finite value",
                       "finite numbers");
    }
    if (static_cast<int>(values.size()) != joints + 1) {
      throw InputError(InputProblem::kSyntax, where, "",
                       "expected " + std::to_string(joints + 1) + " columns (time_s and " +
                           std::to_string(joints) + " joint angles in rad), got " +
                           std::to_string(values.size()));
    }
    if (!times.empty() && !(values[0] > times.back())) {
      throw InputError(InputProblem::kBadValue, where, columns::kTime,
                       "time_s must increase strictly");
    }
    times.push_back(values[0]);
    angles.emplace_back(values.begin() + 1, values.end());
  }
  if (times.size() < 2) {
    throw InputError(InputProblem::kMissing, {path}, "", "gait CSV needs at least two rows");
  }
  return std::make_unique<CsvGait>(path, std::move(times), std::move(angles));
}

}  // namespace ipmc
