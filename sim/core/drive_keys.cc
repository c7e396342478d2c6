#include "sim/core/drive_keys.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/core/key_builder.h"
#include "sim/core/scenario.h"
#include "sim/core/waveform.h"
#include "sim/io/columns.h"
#include "sim/io/csv.h"

namespace ipmc {
std::vector<KeySpec> DriveKeys() {
  using T = KeyType;
  return {
      Key(kDriveModeKey, T::kChoice, "", "", "\"closed_loop\"",
          "closed_loop: the controllers track the wave; sine: each link's voltage "
          "A sin(2 pi f t - (q - 1) phi), f = waveform.frequency_Hz, faded in by the start ramp; "
          "csv: the voltages of a CSV against time (docs/RUNS.md, \"Open loop\")")
          .Default("\"closed_loop\"")
          .Example("\"sine\"")
          .Refused("\"square\"")
          .Choices(kDriveModeNames)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.drive.mode = ChoiceValue(kDriveModeNames, v.Choice());
          })
          .Writes([](const ScenarioConfig& c) {
            return TomlString(ChoiceText(kDriveModeNames, c.drive.mode));
          }),
      Key("drive.amplitude_V", T::kNumber, "V", ">= 0", "1",
          "Sine: every link's voltage amplitude A (the model's ipmc_voltage_limit_V bounds it)")
          .Default("1.0")
          .Example("6.0")
          .Refused("-1")
          .AtLeast(0.0)
          .Only(kDriveModeKey, "sine")
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.drive.amplitude_V = v.Number(); })
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.drive.amplitude_V); }),
      Key("drive.phase_lag_rad", T::kNumber, "rad", "finite", "pi / 2",
          "Sine: the phase lag phi of each link behind the one before it (> 0: the wave runs "
          "from link 1 to the tail)")
          .Default("1.5707963267948966")
          .Example("1.0")
          .Only(kDriveModeKey, "sine")
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.drive.phase_lag_rad = v.Number(); })
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.drive.phase_lag_rad); }),
      Key(kDriveCsvKey, T::kString, "",
          "a readable CSV with columns time_s and voltage1_V..voltageN_V; relative to the "
          "scenario file's folder",
          "none: required with mode = \"csv\"",
          "Csv: the links' voltages [V] against time [s], linearly interpolated (a run's "
          "timeseries.csv is one)")
          .Example("\"head_and_tail_drive.csv\"")
          .Refused("\"no_such_drive.csv\"")
          .Only(kDriveModeKey, "csv")
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.drive.csv = ReadablePath(v, "a CSV of voltages");
          })
          .Writes([](const ScenarioConfig& c) {
            return c.drive.csv.empty() ? kLeftOut : TomlString(c.drive.csv);
          }),
  };
}

OpenLoopVoltages::OpenLoopVoltages(const DriveScenario& drive, double frequency_Hz,
                                   double ramp_s, int links, const std::string& source)
    : drive_(drive), frequency_Hz_(frequency_Hz), ramp_s_(ramp_s), links_(links) {
  if (drive.mode != DriveMode::kCsv) return;
  if (drive.csv.empty()) {
    throw InputError(InputProblem::kMissing, {source}, kDriveCsvKey,
                     std::string(kDriveCsvKey) + " is required with " + kDriveModeKey +
                         " = \"csv\"",
                     "a readable CSV");
  }
  const CsvTable table = CsvTable::Read(drive.csv);
  if (table.Rows() < 1) {
    throw InputError(InputProblem::kMissing, {drive.csv}, "",
                     "a drive CSV needs at least one row of voltages");
  }
  times_s_ = table.FiniteNumbers(columns::kTime);
  for (std::size_t row = 1; row < times_s_.size(); ++row) {
    if (!(times_s_[row] > times_s_[row - 1])) {
      throw InputError(InputProblem::kBadValue,
                       {drive.csv, static_cast<std::uint32_t>(table.Line(row))}, columns::kTime,
                       "time_s must increase strictly", "strictly increasing times");
    }
  }
  for (int q = 1; q <= links; ++q) voltages_V_.push_back(table.FiniteNumbers(columns::Voltage(q)));
}

std::vector<double> OpenLoopVoltages::At(double t_s) const {
  std::vector<double> volts(links_, 0.0);
  if (drive_.mode == DriveMode::kSine) {
    const double ramp = StartRamp(t_s, ramp_s_);
    for (int q = 0; q < links_; ++q) {
      volts[q] = ramp * drive_.amplitude_V *
                 std::sin(kTwoPi * frequency_Hz_ * t_s - q * drive_.phase_lag_rad);
    }
    return volts;
  }
  if (drive_.mode != DriveMode::kCsv) return volts;
  // The row at or before t, and the weight of the next.
  const auto after = std::upper_bound(times_s_.begin(), times_s_.end(), t_s);
  if (after == times_s_.begin() || after == times_s_.end()) {
    const std::size_t row = after == times_s_.begin() ? 0 : times_s_.size() - 1;
    for (int q = 0; q < links_; ++q) volts[q] = voltages_V_[q][row];
    return volts;
  }
  const std::size_t next = after - times_s_.begin(), row = next - 1;
  const double w = (t_s - times_s_[row]) / (times_s_[next] - times_s_[row]);
  for (int q = 0; q < links_; ++q) {
    volts[q] = voltages_V_[q][row] + w * (voltages_V_[q][next] - voltages_V_[q][row]);
  }
  return volts;
}

}  // namespace ipmc
