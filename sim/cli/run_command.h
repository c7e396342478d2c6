// ipmc-swim run: a closed-loop scenario (TOML), or a run's summary.json
// run again, with --set KEY=VALUE and --cycles overrides, its outputs
// (timeseries.csv, states.csv, summary.json) and optionally its film.
//
//   ipmc-swim run SCENARIO [--set KEY=VALUE ...] [--cycles N] [--out DIR]
//       [--format mat,h5] [--video FILE.mp4 ...] [--allow-long]
//
// The options are sim/runs/run_command.h's table (planned and written
// there, as from Python), besides the video options of `render`; the run
// is sim/runs/closed_loop_run.h.
#pragma once

#include <CLI/CLI.hpp>

#include "renders/swim_film.h"
#include "sim/cli/option_flags.h"
#include "sim/runs/run_command.h"

namespace ipmc {

struct RunArgs : TableCommand<RunCommand> {
  FilmConfig film;
};

// Adds subcommand "run" to app, storing options in args.
void AddRunCommand(CLI::App& app, RunArgs& args);

// Runs the scenario, prints its results and writes its files.
// The exit status, or -1 when the command line chose another command.
int RunRunCommandLine(const RunArgs& args);

}  // namespace ipmc
