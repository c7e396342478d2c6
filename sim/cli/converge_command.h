// ipmc-swim converge: the scenario's gait at more segments per link, halved
// steps and finer plates (sim/runs/converge_study.h), in parallel:
//
//   ipmc-swim converge SCENARIO.toml [--out DIR] [--max-segments N]
//                      [--halvings N] [--max-plates-k K] [--cycles N] [--jobs N]
//
// Prints, per study, each run's swim and fluid power with their errors
// against the study's converged reference (with the reference's own
// uncertainty), the cost per simulated second, and which settings reach
// 1 %; writes DIR/converge.csv and DIR/converge.png (|swim error| against
// cost, one curve per study).
#pragma once

#include <CLI/CLI.hpp>

#include "sim/cli/option_flags.h"
#include "sim/runs/converge_study.h"

namespace ipmc {

using ConvergeArgs = TableCommand<ConvergeCommand>;

void AddConvergeCommand(CLI::App& app, ConvergeArgs& args);

// Runs it and prints, if the command line chose it; returns its exit code,
// or -1 if it was not chosen.
int RunConvergeCommandLine(const ConvergeArgs& args);

}  // namespace ipmc
