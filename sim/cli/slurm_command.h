// The cluster side of the sweep commands (sim/batch/slurm.h,
// sim/batch/sweep_status.h):
//
//   ipmc-swim sweep SWEEP.toml --slurm DIR [--array-size N] [--partition P]
//                   [--time T] [--cpus-per-task C] [--dry-run]
// Checks the options (array size in [1, points], a time limit Slurm
// reads, sbatch on the PATH unless --dry-run) and DIR's journals (they
// must be of this sweep), writes DIR/sweep.sbatch and DIR/merge.sbatch,
// submits both with sbatch (the merge after the array, afterany) and
// prints the job ids; --dry-run stops before submitting.
//
//   ipmc-swim sweep --status DIR
// Lists the points done, failed (with their errors) and missing, from the
// journals in DIR and DIR/shards.
//
//   ipmc-swim merge --partial --out PREFIX A.csv B.csv ...
// Merges the tables that exist (for one that does not, the points its
// journal recorded) and lists the missing points.
#pragma once

#include <CLI/CLI.hpp>

#include "sim/cli/sweep_command.h"

namespace ipmc {

// Adds --slurm, --array-size, --partition, --time, --cpus-per-task,
// --dry-run and --status to the sweep subcommand.
void AddSlurmOptions(CLI::App* sweep, SweepArgs& args);

int RunSlurmSubmission(const SweepArgs& args);
int RunSweepStatus(const std::string& dir);
int RunPartialMerge(const SweepArgs& args);

}  // namespace ipmc
