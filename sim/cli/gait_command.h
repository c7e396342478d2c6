// ipmc-swim gait: a prescribed joint-space gait (sine, square or from a
// CSV) on a model with servo_* actuators, and the swim it makes.
//
//   ipmc-swim gait [--model M] [--gait sine|square|csv] [--frequency-hz f]
//       [--amplitude-rad A] [--phase-lag-rad phi] [--amplitudes-rad ...]
//       [--phases-rad ...] [--csv FILE] [--cycles N] [--samples-per-cycle K]
//       [--out DIR] [--allow-long]
// Prints the per-cycle displacements, the mean speed and the servos'
// tracking; --out DIR writes timeseries.csv, states.csv and summary.json.
// The options are the table GaitOptions() and the run RunGaitCommand of
// sim/runs/gait_command.h.
#pragma once

#include <CLI/CLI.hpp>

#include "sim/cli/option_flags.h"
#include "sim/runs/gait_command.h"

namespace ipmc {

using GaitArgs = TableCommand<GaitCommand>;

// Adds subcommand "gait" to app, storing its options in args.
void AddGaitCommand(CLI::App& app, GaitArgs& args);

// Runs it and prints, if the command line chose it; returns its exit code,
// or -1 if it was not chosen.
int RunGaitCommandLine(const GaitArgs& args);

}  // namespace ipmc
