// ipmc-swim optimize: a scenario's design optimised for a metric
// (docs/OPTIMIZE.md; the options, checks, runs and files are those of
// sim/optimize/optimize_run.h, as from Python).
//
//   ipmc-swim optimize OPT.toml --out DIR [--jobs N] [--resume]
//   ipmc-swim optimize OPT.toml --out DIR --slurm [--partition P] [--time T] [--dry-run]
// Reads the whole optimisation file first (a bad field stops it with one
// line and no output), then runs the starts on N threads. Progress goes to
// stderr, one line per evaluation. Ctrl-C stops at the next evaluation
// (the running ones finish and are recorded in DIR/optimize.journal; exit
// code 130); --resume goes on from the journal. Prints the best design
// and where the files are. --slurm writes the job array and merge job
// into DIR and submits them (sbatch) instead of running here.
#pragma once

#include <CLI/CLI.hpp>

#include "sim/cli/option_flags.h"
#include "sim/optimize/optimize_run.h"
#include "sim/optimize/optimize_slurm.h"

namespace ipmc {

struct OptimizeArgs : TableCommand<OptimizeCommand> {
  bool slurm = false;   // --slurm: submit to Slurm into --out (sim/optimize/optimize_slurm.h)
  SlurmOptions slurm_options;
  bool dry_run = false;
};

// Adds subcommand "optimize" to app, storing its options in args.
void AddOptimizeCommand(CLI::App& app, OptimizeArgs& args);

// Runs it and prints, if the command line chose it; returns its exit
// code, or -1 if it was not chosen.
int RunOptimizeCommandLine(const OptimizeArgs& args);

}  // namespace ipmc
