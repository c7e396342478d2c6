// How a run drives its links, as scenario keys ([drive]): closed loop (the
// controllers of [controller] track the wave of [waveform], the paper's
// section 5), or open loop, each link's voltage given in advance:
//
//   sine:  V_q(t) = A sin(2 pi f t - (q - 1) phi) ramp(t)     [V], q = 1..N
//          f = waveform.frequency_Hz (the run's cycles are its periods),
//          phi = drive.phase_lag_rad (> 0: the wave runs from link 1 to
//          link N), ramp the start ramp of waveform.start_ramp_cycles
//          (StartRamp, sim/core/waveform.h);
//   csv:   a CSV with the columns time_s and voltage1_V..voltageN_V (a
//          run's timeseries.csv is one), linearly interpolated in time,
//          its first row's voltages before it and its last row's after.
//
// Either way the voltages are set at the controller's samples
// (controller.sample_rate_Hz) and held between them, as the controllers'
// are, and the run measures the same swim and writes the same files.
#pragma once

#include <string>
#include <vector>

#include "sim/core/choice_table.h"
#include "sim/core/scenario_keys.h"

namespace ipmc {

enum class DriveMode { kClosedLoop, kSine, kCsv };

inline constexpr ChoiceName<DriveMode> kDriveModeNames[] = {
    {"closed_loop", DriveMode::kClosedLoop},
    {"sine", DriveMode::kSine},
    {"csv", DriveMode::kCsv},
};

// [drive].
struct DriveScenario {
  DriveMode mode = DriveMode::kClosedLoop;
  double amplitude_V = 1.0;       // sine: A, >= 0
  double phase_lag_rad = 1.5707963267948966;  // sine: phi, pi / 2
  std::string csv;                // csv: the file, absolute
  bool OpenLoop() const { return mode != DriveMode::kClosedLoop; }
};

// The [drive] keys of the key table, in its order.
std::vector<KeySpec> DriveKeys();

// The voltages of an open-loop drive for a model of `links` links, at
// wave frequency frequency_Hz with the start ramp over ramp_s.
class OpenLoopVoltages {
 public:
  // Reads and checks the CSV of a csv drive; throws InputError
  // (sim/base/error.h) "SOURCE: drive.csv is required ..." without one, or
  // "CSV:LINE: ..." naming the column: no time_s or voltage<q>_V column
  // for a link, no row, times not strictly increasing, a value not finite.
  OpenLoopVoltages(const DriveScenario& drive, double frequency_Hz, double ramp_s, int links,
                   const std::string& source);
  // Every link's voltage [V] at t [s].
  std::vector<double> At(double t_s) const;

 private:
  DriveScenario drive_;
  double frequency_Hz_, ramp_s_;
  int links_;
  std::vector<double> times_s_;
  std::vector<std::vector<double>> voltages_V_;  // per link, per row
};

}  // namespace ipmc
