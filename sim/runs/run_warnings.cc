#include "sim/runs/run_warnings.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ipmc {
namespace {

enum Check { kReynolds, kClamp, kTracking, kReach, kStepping, kTimestep };

std::string Percent(double share) {
  std::ostringstream text;
  text.precision(3);
  text << 100.0 * share << " %";
  return text.str();
}

}  // namespace

int RunWarnings::Count() const {
  return static_cast<int>(std::count(std::begin(failed), std::end(failed), true));
}

RunWarnings ClosedLoopWarnings(const ClosedLoopResult& result) {
  RunWarnings warnings;
  const SwimMetrics& swim = result.swim;
  // Its message is the swim's own (FluidWarnings, sim/core/swim_meter.h).
  warnings.failed[kReynolds] = swim.LargestReynolds() > kReynoldsWarning;
  // Its message too (StepResolutionWarnings, sim/core/step_resolution.h).
  warnings.failed[kTimestep] = !swim.step.Resolved();
  const int driven = result.actuation == Actuation::kSingle ? 1 : static_cast<int>(result.links.size());
  for (int q = 0; q < driven && q < static_cast<int>(result.links.size()); ++q) {
    const LinkTracking& link = result.links[q];
    const std::string name = "link " + std::to_string(q + 1);
    if (link.clamped_fraction > kClampShareWarning) {
      warnings.failed[kClamp] = true;
      warnings.messages.push_back(name + " is at the clamp in " + Percent(link.clamped_fraction) +
                                  " of the samples (above " + Percent(kClampShareWarning) +
                                  "): it cannot make the voltage its reference needs");
    }
    // In open loop there is no reference to follow.
    if (!result.open_loop && link.max_abs_error_mm > link.max_abs_reference_mm) {
      std::ostringstream message;
      message.precision(4);
      message << name << "'s peak tracking error " << link.max_abs_error_mm
              << " mm is above its reference's amplitude " << link.max_abs_reference_mm
              << " mm: it does not follow the wave";
      warnings.failed[kTracking] = true;
      warnings.messages.push_back(message.str());
    }
  }
  if (result.reach_clamps > 0) {
    warnings.failed[kReach] = true;
    warnings.messages.push_back(
        "a link's free deflection exceeded the link's reach in " +
        std::to_string(result.reach_clamps) +
        " actuator updates and was clamped: the reference asks for more bending than the link has");
  }
  const EnergyMetrics& energy = result.energy;
  const double actuator_W = std::abs(energy.actuator_power_W_total);
  if (actuator_W > 0.0 && std::abs(energy.stepping_power_W) > kSteppingShareWarning * actuator_W) {
    warnings.failed[kStepping] = true;
    warnings.messages.push_back(
        "the time step's own power is " +
        Percent(std::abs(energy.stepping_power_W / energy.actuator_power_W_total)) +
        " of the actuators' (above " + Percent(kSteppingShareWarning) +
        "): the energy figures measure the integrator; a smaller timestep_s shrinks it");
  }
  return warnings;
}

std::vector<std::string> ClosedLoopWarningLines(const ClosedLoopResult& result) {
  std::vector<std::string> lines = result.swim.warnings;
  const RunWarnings warnings = ClosedLoopWarnings(result);
  lines.insert(lines.end(), warnings.messages.begin(), warnings.messages.end());
  return lines;
}

std::vector<std::string> RunWarningColumns() {
  std::vector<std::string> names = {kWarningsColumn};
  for (const RunWarningCheck& check : kRunWarningChecks) names.push_back(check.column);
  return names;
}

std::vector<std::string> RunWarningCells(const RunWarnings& warnings) {
  std::vector<std::string> cells = {std::to_string(warnings.Count())};
  for (bool failed : warnings.failed) cells.push_back(failed ? "1" : "0");
  return cells;
}

std::vector<int> FailedChecks(const std::vector<std::string>& columns,
                              const std::vector<std::string>& row) {
  std::vector<int> failed;
  for (int c = 0; c < kRunWarningCheckCount; ++c) {
    const auto it = std::find(columns.begin(), columns.end(), kRunWarningChecks[c].column);
    const size_t at = static_cast<size_t>(it - columns.begin());
    if (it != columns.end() && at < row.size() && row[at] == "1") failed.push_back(c);
  }
  return failed;
}

std::string WarningCountsText(const std::vector<std::string>& columns,
                              const std::vector<std::vector<std::string>>& rows) {
  if (std::find(columns.begin(), columns.end(), kWarningsColumn) == columns.end()) return "";
  int warned = 0;
  int counts[kRunWarningCheckCount] = {};
  for (const std::vector<std::string>& row : rows) {
    const std::vector<int> failed = FailedChecks(columns, row);
    warned += !failed.empty();
    for (int c : failed) ++counts[c];
  }
  if (warned == 0) return "none with warnings";
  std::string text = std::to_string(warned) + " with warnings:";
  const char* separator = " ";
  for (int c = 0; c < kRunWarningCheckCount; ++c) {
    if (counts[c] == 0) continue;
    text += separator + std::string(kRunWarningChecks[c].label) + " (" +
            std::to_string(counts[c]) + ")";
    separator = ", ";
  }
  return text;
}

}  // namespace ipmc
