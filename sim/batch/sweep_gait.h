// Sweeps of prescribed gaits: a sweep file whose [gait] table (the options
// of `ipmc-swim gait`, sim/runs/gait_command.h) replaces `base`, so that
// every point runs that gait instead of a closed-loop scenario:
//
//   [gait]                          # the gait every point starts from
//   model = "../models/flagellum3.xml"   # relative to the sweep file
//   gait = "sine"
//   frequency_Hz = 0.5
//   cycles = 2
//   [grid]                          # gait options, each an array of values
//   phase_lag_rad = [0.0, 1.0, 2.0]
//   amplitude_rad = [0.2, 0.3]
//
// [set], [grid], [[point]] and keep_runs work as for scenario sweeps
// (sim/batch/sweep_file.h), with the gait's option names (`ipmc-swim
// options`, gait) for keys: model, gait, frequency_Hz, amplitude_rad,
// phase_lag_rad, amplitudes_rad, phases_rad, csv, cycles,
// samples_per_cycle, allow_long (not out: a point's run directory is
// keep_runs's). The table's results are the gait's metrics, the numbers
// `ipmc-swim gait` reports (kGaitResults); a gait sweep has no
// closed-loop columns (no links, voltages or energies: a prescribed gait
// has no controller or actuator model). A point runs exactly what
// `ipmc-swim gait` with the same options runs; with keep_runs its run
// directory holds the files `gait --out` writes.
#pragma once

#include <string>
#include <vector>

#include <toml++/toml.h>

#include "sim/batch/sweep_file.h"
#include "sim/runs/gait_command.h"

namespace ipmc {

// The result columns of a gait sweep's table, after point, the swept keys,
// status and error.
extern const std::vector<std::string> kGaitResults;

// The sweep file key of the gait table.
constexpr char kGaitSweepKey[] = "gait";

// Reads a sweep file with a [gait] table (root, parsed from `source`).
// Throws InputError "SOURCE:LINE: key ..." for an unknown option, a value
// of the wrong type or a bad grid, before anything runs.
SweepPlan ReadGaitSweep(const toml::table& root, const std::string& source);

// A point's options as text, one "name = value" line per option (the
// journal's fingerprint and the table's provenance).
std::string GaitCommandText(const GaitCommand& command);

// One point's row cells after status and error (kGaitResults), or empty
// cells if `result` is null.
std::vector<std::string> GaitResultCells(const GaitRunResult* result);

}  // namespace ipmc
