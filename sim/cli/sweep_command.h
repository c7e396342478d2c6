// The sweep subcommands of ipmc-swim (sim/batch/sweep.h describes sweep files
// and the table).
//
//   ipmc-swim sweep SWEEP.toml --out PREFIX [--jobs N] [--shard i/n]
// Reads the whole sweep first (a malformed file, an unknown or ill-typed
// key stops it with one line and no output), then runs its points, or
// only shard i of n (the points with index % n == i - 1), on N threads
// (default: the number of hardware threads). A point that fails is
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
// ordered by point index; tables with different columns, a point in two
// tables or a gap in the indices are one-line errors.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace ipmc {

struct SweepArgs {
  std::string sweep_path;
  int jobs = 1;  // AddSweepCommands sets the default: std::thread::hardware_concurrency()
  std::string shard = "1/1";
  std::string out_prefix;
  std::vector<std::string> merge_tables;
  std::string merge_out_prefix;
};

// Adds subcommands "sweep" and "merge" to app, storing options in args.
void AddSweepCommands(CLI::App& app, SweepArgs& args);

// Runs the subcommand that app parsed; returns its exit code, or -1 if
// neither was chosen. Throws std::invalid_argument for bad option values
// and std::runtime_error for bad files and output failures.
int RunSweepCommand(const CLI::App& app, const SweepArgs& args);

}  // namespace ipmc
