#include "renders/figure_labels.h"

#include <algorithm>
#include <optional>
#include <string>

#include "sim/base/numbers.h"

namespace ipmc {
namespace {

struct LabelEntry {
  const char* column;
  const char* label;
};

// Every column the program's CSV files and sweep tables carry that a
// figure puts on an axis, with its label and unit.
constexpr LabelEntry kLabels[] = {
    {"time_s", "time t [s]"},
    {"w_rad_s", "angular frequency w [rad/s]"},
    {"frequency_Hz", "frequency f [Hz]"},
    {"com_x_mm", "centre of mass x [mm]"},
    {"com_y_mm", "centre of mass y [mm]"},
    {"head_x_mm", "head x [mm]"},
    {"head_y_mm", "head y [mm]"},
    {"yaw_rad", "head yaw [rad]"},
    {"coherence", "coherence"},
    {"mean_speed_along_mm_s", "mean speed along the swimming axis [mm/s]"},
    {"last_cycle_com_along_mm", "centre of mass swim in the last cycle [mm]"},
    {"reynolds_tip", "Reynolds number, tip"},
    {"reynolds_swim", "Reynolds number, swimming"},
    {"actuation", "actuation"},
    {"plants", "link plants"},
    {"cycles", "cycles"},
    {"segments_per_link", "rigid segments per link"},
    {"timestep_s", "time step [s]"},
    {"waveform.frequency_Hz", "wave frequency f [Hz]"},
    {"waveform.wavelength_mm", "wavelength [mm]"},
    {"waveform.c0_um", "wave amplitude c0 [um]"},
    {"waveform.c1_um_per_mm", "wave amplitude slope c1 [um/mm]"},
    {"waveform.c2_um_per_mm2", "wave amplitude curvature c2 [um/mm^2]"},
    {"waveform.c_um", "wave amplitude c [um/mm^alpha]"},
    {"waveform.alpha", "wave growth exponent alpha"},
    {"fluid.viscosity_Pa_s", "viscosity mu [Pa s]"},
    {"controller.kind", "controller"},
    {"controller.kp", "proportional gain Kp [V/mm]"},
    {"controller.ki", "integral gain Ki [V/(mm s)]"},
    {"controller.kd", "derivative gain Kd [V s/mm]"},
    {"controller.v_max_V", "voltage limit [V]"},
    {"controller.sample_rate_Hz", "controller sample rate [Hz]"},
    {"link_lengths_mm", "link lengths [mm]"},
};

// Per-link sweep results "link<q>_<result>".
constexpr LabelEntry kLinkResultLabels[] = {
    {"iae_mm_s", "IAE [mm s]"},
    {"itae_mm_s2", "ITAE [mm s^2]"},
    {"rms_voltage_V", "RMS voltage [V]"},
    {"clamped_fraction", "fraction of samples at the clamp"},
};

// Numbered columns PREFIX<q>SUFFIX (sim/io/columns.h): "<noun> q label".
struct NumberedLabel {
  const char* prefix;
  const char* suffix;
  const char* noun;
  const char* label;
};
constexpr NumberedLabel kNumberedLabels[] = {
    {"reference", "_mm", "link", "reference deflection [mm]"},
    {"measured", "_mm", "link", "measured deflection [mm]"},
    {"voltage", "_V", "link", "voltage [V]"},
    {"relative", "_mm", "link", "relative tip deflection [mm]"},
    {"free", "_mm", "link", "free tip deflection [mm]"},
    {"tip", "_lateral_mm", "link", "tip lateral position [mm]"},
    {"tip", "_x_mm", "tip", "x [mm]"},
    {"tip", "_y_mm", "tip", "y [mm]"},
    {"y_link", "", "link", "step response [mm]"},
    {"u_link", "", "link", "voltage in the step [V]"},
    {"q_ref", "_rad", "joint", "reference angle [rad]"},
    {"q", "_rad", "joint", "angle [rad]"},
};

// Unit suffixes of names not in the tables, longest first.
constexpr LabelEntry kUnitSuffixes[] = {
    {"_um_per_mm", "um/mm"},
    {"_mm_s2", "mm/s^2"},
    {"_rad_s", "rad/s"},
    {"_kg_m3", "kg/m^3"},
    {"_Pa_s", "Pa s"},
    {"_mm_s", "mm/s"},
    {"_mm", "mm"},
    {"_um", "um"},
    {"_Hz", "Hz"},
    {"_rad", "rad"},
    {"_deg", "deg"},
    {"_dB", "dB"},
    {"_V", "V"},
    {"_s", "s"},
};

std::string SpelledOut(std::string name) {
  std::string unit;
  for (const LabelEntry& suffix : kUnitSuffixes) {
    const std::string tail = suffix.column;
    if (name.size() > tail.size() &&
        name.compare(name.size() - tail.size(), tail.size(), tail) == 0) {
      name.erase(name.size() - tail.size());
      unit = suffix.label;
      break;
    }
  }
  std::replace(name.begin(), name.end(), '_', ' ');
  std::replace(name.begin(), name.end(), '.', ' ');
  return unit.empty() ? name : name + " [" + unit + "]";
}

}  // namespace

std::string AxisLabel(const std::string& column) {
  for (const LabelEntry& entry : kLabels) {
    if (column == entry.column) return entry.label;
  }
  // An array element of a sweep table: "link_lengths_mm[0]" -> link 1.
  const size_t open = column.find('[');
  if (open != std::string::npos && column.back() == ']') {
    const std::string base = column.substr(0, open);
    const std::optional<long> index =
        ParseInteger(column.substr(open + 1, column.size() - open - 2));
    if (base == "link_lengths_mm" && index)
      return "link " + std::to_string(*index + 1) + " length [mm]";
    return AxisLabel(base) + " (element " + column.substr(open + 1, column.size() - open - 2) + ")";
  }
  for (const NumberedLabel& entry : kNumberedLabels) {
    const std::string prefix = entry.prefix, suffix = entry.suffix;
    if (column.size() <= prefix.size() + suffix.size() || column.rfind(prefix, 0) != 0 ||
        column.compare(column.size() - suffix.size(), suffix.size(), suffix) != 0) {
      continue;
    }
    const std::optional<long> q =
        ParseInteger(column.substr(prefix.size(), column.size() - prefix.size() - suffix.size()));
    if (q && *q > 0) return std::string(entry.noun) + " " + std::to_string(*q) + " " + entry.label;
  }
  // "link<q>_<result>" of a sweep table.
  if (column.rfind("link", 0) == 0) {
    const size_t underscore = column.find('_');
    const std::optional<long> link = underscore == std::string::npos
                                         ? std::nullopt
                                         : ParseInteger(column.substr(4, underscore - 4));
    if (link) {
      const std::string result = column.substr(underscore + 1);
      for (const LabelEntry& entry : kLinkResultLabels) {
        if (result == entry.column) return "link " + std::to_string(*link) + " " + entry.label;
      }
    }
  }
  return SpelledOut(column);
}

}  // namespace ipmc
