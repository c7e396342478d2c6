// Test-bench experiments (paper section 4.1): a voltage signal on chosen
// links of a (usually clamped) flagellum, recorded like the bench's data
// acquisition at a fixed rate (default 1 kHz): voltages, the links'
// relative tip deflections, the tips' lateral positions (the laser), and
// the links' free deflections from their models.
//
//   sine:  V(t) = A sin(2 pi f t)
//   chirp: V(t) = A sin(2 pi (f0 t + (f1 - f0) t^2 / (2 T)))  (linear sweep)
// The paper's chirp: A = 3 V, f0 = 0.1 Hz, f1 = 200 Hz, T = 200 s.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "sim/core/simulation.h"
#include "sim/io/csv.h"

namespace ipmc {

struct BenchSignal {
  enum class Kind { kSine, kChirp };
  Kind kind = Kind::kSine;
  double amplitude_V = 3.0;      // finite, |A| <= 100
  double frequency_Hz = 1.0;     // sine; > 0
  double start_Hz = 0.1;         // chirp f0; > 0
  double end_Hz = 200.0;         // chirp f1; > f0, below half the sample rate
  double duration_s = 200.0;     // > 0
  double sample_rate_Hz = 1000;  // > 0, a whole number of time steps
  std::vector<int> driven_links = {1};  // 1-based
  bool allow_long = false;       // lift the run size limits (sim/core/step_count.h)
  void Validate() const;         // FieldError naming the field (amplitude_V, ...)
  double VoltageAt(double t_s) const;
};

struct BenchRecord {
  std::vector<double> t_s;
  std::vector<std::vector<double>> voltage_V;        // [link][sample]
  std::vector<std::vector<double>> relative_mm;      // L_q sin(theta_q)
  std::vector<std::vector<double>> tip_lateral_mm;   // laser
  std::vector<std::vector<double>> free_mm;          // delta_free_q
};

// Called at every sample with the simulated time [s], e.g. to report
// progress; an exception it throws ends the run.
using BenchProgress = std::function<void(double t_s)>;

// Runs `signal` from t = 0 (the state as reset) for its duration and keeps
// the samples from `record_from_s` on. Throws on a bad signal, a model
// without IPMC actuators, or divergence.
BenchRecord RunBench(Simulation& sim, const BenchSignal& signal, double record_from_s = 0.0,
                     const BenchProgress& progress = {});

// The record by the columns of its CSV (BenchCsv) and of the Python
// module's arrays: time_s, then per link voltage<q>_V, relative<q>_mm,
// tip<q>_lateral_mm and free<q>_mm.
NamedColumns BenchColumns(const BenchRecord& record);
std::string BenchCsv(const BenchRecord& record);

}  // namespace ipmc
