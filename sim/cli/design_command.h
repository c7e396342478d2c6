// ipmc-swim design: the controller design of section 5.2 on each link's
// Table 2 model.
//
//   ipmc-swim design [--links 1,2,3] [--plant g1|g2] [--crossover-rad-s 5]
//       [--phase-margin-deg 75] [--reference-order 1.16] [--horizon-s 2]
//       [--sample-rate-hz 10000]
// For each link, on its Table 2 model: the analytic fractional integrator K/s^lambda
// for the crossover and phase margin, with the margins of its exact open
// loop; the PID tuned by Nelder-Mead against the reference model
// 1/((s/w_c)^gamma + 1) over the horizon, with J of eq. 11 at the paper's
// gains (eq. 12) and at the tuned gains, per start.
//
// The options are the table DesignOptions() of
// sim/identify/identify_run.h, which the Python module reads too; the
// computation, its checks and its files are RunDesignCommand there.
// Nothing is written unless the command succeeded, and each file is
// written atomically.
#pragma once

#include <CLI/CLI.hpp>

#include "sim/cli/option_flags.h"
#include "sim/identify/identify_run.h"

namespace ipmc {

using DesignArgs = TableCommand<DesignCommand>;

// Adds subcommand "design" to app, storing its options in args.
void AddDesignCommand(CLI::App& app, DesignArgs& args);

// Runs it and prints, if the command line chose it; returns its exit code,
// or -1 if it was not chosen. Throws FieldError (with the flag in place of
// the field) for bad options, InputError for bad data and
// std::runtime_error for simulation or output failures.
int RunDesignCommandLine(const DesignArgs& args);

}  // namespace ipmc
