// What a closed-loop run's numbers should be read with: the checks a run
// can fail, decided here once for every front end (the run's printout and
// summary.json, sweep and optimisation tables, sweep figures).
//
//   reynolds  the peak tip, the swimming or the oscillatory Reynolds
//             number above kReynoldsWarning (1): every drag model here is
//             Stokes flow
//   clamp     a driven link at the +-v_max clamp in more than 25 % of the
//             controller samples of the metric cycles
//   tracking  a driven link's peak tracking error above the amplitude of
//             its reference (it does not follow the wave)
//   reach     a link's free deflection beyond the link's reach, clamped
//             by the coupling (plugin/actuators/ipmc_actuators.h)
//   stepping  the time step's own power (sim/core/energy.h) above 25 % of
//             the actuators' mean power: the energy figures measure the
//             integrator, not the swimmer
//   timestep  an inertial run's step whose estimated swim error is above
//             1 % or that steps over a drag relaxation
//             (sim/core/step_resolution.h)
#pragma once

#include <iterator>
#include <string>
#include <vector>

#include "sim/runs/closed_loop_run.h"

namespace ipmc {

// The share of samples at the clamp above which a link warns.
constexpr double kClampShareWarning = 0.25;
// The time step's share of the actuators' power above which a run warns.
constexpr double kSteppingShareWarning = 0.25;

// One check: its table column (1 where the run failed it, else 0) and its
// short label for counts ("Re > 1").
struct RunWarningCheck {
  const char* column;
  const char* label;
};
inline constexpr RunWarningCheck kRunWarningChecks[] = {
    {"warn_reynolds", "Re > 1"},
    {"warn_clamp", "clamp > 25 %"},
    {"warn_tracking", "tracking error > reference"},
    {"warn_reach", "link reach clamped"},
    {"warn_stepping", "time step > 25 % of actuator power"},
    {"warn_timestep", "time step too coarse for the swim"},
};
constexpr int kRunWarningCheckCount = static_cast<int>(std::size(kRunWarningChecks));
// The table column counting a run's failed checks.
constexpr char kWarningsColumn[] = "warnings";

struct RunWarnings {
  bool failed[kRunWarningCheckCount] = {};  // by kRunWarningChecks
  std::vector<std::string> messages;         // one line per failed check
  int Count() const;
};

// The checks of a closed-loop run (its metrics over the metric cycles).
RunWarnings ClosedLoopWarnings(const ClosedLoopResult& result);

// Every warning of the run, one line each: the swim's (SwimMetrics::
// warnings, which include the Reynolds number's) and the other checks'.
std::vector<std::string> ClosedLoopWarningLines(const ClosedLoopResult& result);

// Table columns: kWarningsColumn, then each check's column.
std::vector<std::string> RunWarningColumns();
// A run's cells for those columns: the count, then 1 or 0 per check.
std::vector<std::string> RunWarningCells(const RunWarnings& warnings);

// The checks a table row failed (indices into kRunWarningChecks), read
// from the checks' columns by name: none if the table has none of them or
// the row's cells are empty (a failed point).
std::vector<int> FailedChecks(const std::vector<std::string>& columns,
                              const std::vector<std::string>& row);

// How many of a table's rows warn, and for what: "8 with warnings: Re > 1
// (8), clamp > 25 % (5)", or "none with warnings" ("" for a table without
// warning columns).
std::string WarningCountsText(const std::vector<std::string>& columns,
                              const std::vector<std::vector<std::string>>& rows);

}  // namespace ipmc
