// ipmc-swim bench: a voltage experiment on the test bench (paper section
// 4.1), recorded like the laser meter (sim/runs/bench_run.h).
//
//   ipmc-swim bench --out FILE.csv [--model M] [--signal sine|chirp]
//       [--amplitude-v A] [--frequency-hz f] [--start-hz f0] [--end-hz f1]
//       [--duration-s T] [--links 1,2] [--sample-rate-hz 1000] [--allow-long]
// Writes the record (time_s, voltage<q>_V, relative<q>_mm,
// tip<q>_lateral_mm, free<q>_mm) and prints each link's peak relative tip
// deflection. The options are the table BenchOptions() and the run
// RunBenchCommand of sim/runs/bench_command.h, which the Python module
// calls too (so both refuse an --out that is the model); here --out is
// required.
#pragma once

#include <CLI/CLI.hpp>

#include "sim/cli/option_flags.h"
#include "sim/runs/bench_command.h"

namespace ipmc {

using BenchArgs = TableCommand<BenchCommand>;

// Adds subcommand "bench" to app, storing its options in args.
void AddBenchCommand(CLI::App& app, BenchArgs& args);

// Runs it and prints, if the command line chose it; returns its exit code,
// or -1 if it was not chosen.
int RunBenchCommandLine(const BenchArgs& args);

}  // namespace ipmc
