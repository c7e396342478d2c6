// Prescribed joint-space gaits for the kinematic mode: each driven hinge
// follows a reference angle q_ref(t) [rad] through a stiff servo.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace ipmc {

struct JointReference {
  std::vector<double> angle_rad;
  std::vector<double> velocity_rad_s;
};

class Gait {
 public:
  virtual ~Gait() = default;
  virtual int Joints() const = 0;
  virtual double Period_s() const = 0;
  virtual JointReference At(double t_s) const = 0;
  virtual std::string Describe() const = 0;
};

// q_j(t) = A_j sin(2 pi f t + phi_j).
struct SineGaitConfig {
  double frequency_Hz = 0.01;
  std::vector<double> amplitude_rad;
  std::vector<double> phase_rad;
  void Validate() const;  // throws FieldError naming the field and its range
};
std::unique_ptr<Gait> MakeSineGait(const SineGaitConfig& config);

// Travelling wave along the hinges: phase_j = -j * phase_lag_rad, so a
// positive lag sends the wave from head to tail and the swimmer forward.
SineGaitConfig TravellingWave(int joints, double frequency_Hz, double amplitude_rad,
                              double phase_lag_rad);

// Square stroke in joint space: each joint follows a periodic square wave
// between -A and +A whose transitions are half-cosine ramps lasting a
// quarter period; joint j lags joint j-1 by a quarter period, so two
// joints trace a rectangle (Purcell's stroke).
struct SquareStrokeConfig {
  double frequency_Hz = 0.01;
  double amplitude_rad = 0.5;
  int joints = 2;
  void Validate() const;  // throws FieldError naming the field and its range
};
std::unique_ptr<Gait> MakeSquareStroke(const SquareStrokeConfig& config);

// Trajectory from CSV (sim/io/csv.h): rows "time_s, q_1, ..., q_n" [s,
// rad], an optional header line, strictly increasing times; linear
// interpolation, repeated with period t_last - t_first. Throws InputError
// (sim/base/error.h, a std::runtime_error) "PATH:LINE: reason".
std::unique_ptr<Gait> LoadCsvGait(const std::string& path, int joints);

}  // namespace ipmc
