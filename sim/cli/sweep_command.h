// The sweep subcommands of ipmc-swim (sim/batch/sweep.h describes sweep files
// and the table).
//
//   ipmc-swim sweep SWEEP.toml --out PREFIX [--jobs N] [--shard i/n]
// Reads the whole sweep first (a malformed file, an unknown or ill-typed
// key stops it with one line and no output), then runs its points, or
// only shard i of n (the points with index % n == i - 1), on N threads
// (default: the CPUs the process may run on, its affinity mask). Each
// finished point goes to PREFIX.journal (sim/batch/journal.h); running
// the same sweep into the same PREFIX again runs only the points it does
// not hold. Ctrl-C stops at the next point boundary (the running points
// finish and are recorded; exit code 130) and says how to resume. A point that fails is
// recorded in its row and the others still run. Progress goes to stderr:
// a bar with runs done/total and the ETA, redrawn in place, when stderr
// is a terminal; else one line per point, "run k/N done (point i)" or
// "run k/N failed (point i): reason". Writes PREFIX.csv and PREFIX.json
// (each atomically, creating PREFIX's directory) and prints a short
// table of the swept values, status and speed on stdout. The exit code is
// 0 once the table is written, failed points included.
//
//   ipmc-swim merge --out PREFIX A.csv B.csv ...
// Joins the tables of a sweep's shards into PREFIX.csv and PREFIX.json,
// ordered by point index; a table that does not exist, tables with
// different columns, a point in two tables or a gap in the indices are
// one-line errors. With --partial: sim/cli/slurm_command.h.
//
// sweep --slurm DIR and sweep --status DIR: sim/cli/slurm_command.h.
// The options are the tables of sim/batch/sweep_command.h (checked and
// written there, as from Python), besides the Slurm ones.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "sim/batch/slurm.h"
#include "sim/batch/sweep_command.h"
#include "sim/cli/option_flags.h"

namespace ipmc {

struct SweepArgs {
  TableCommand<SweepCommand> sweep;
  TableCommand<MergeCommand> merge;
  SlurmOptions slurm;  // sweep --slurm DIR (sim/cli/slurm_command.h)
  bool dry_run = false;
  std::string status_dir;  // sweep --status DIR
};

// Adds subcommands "sweep" and "merge" to app, storing options in args.
void AddSweepCommands(CLI::App& app, SweepArgs& args);

// Runs the subcommand that app parsed; returns its exit code, or -1 if
// neither was chosen. Throws FieldError for bad option values and
// std::runtime_error for bad files and output failures.
int RunSweepCommandLine(const CLI::App& app, const SweepArgs& args);

}  // namespace ipmc
