// ipmc-swim bode: the open loop of one link in the frequency domain (paper section 5.2).
//
//   ipmc-swim bode --controller pid|fractional|fractional-eq15|
//                  fractional-oustaloup|none [--links 1,2,3] [--plant g1|g2] ...
// For each link in --links, the open loop L = C x P_link with the exact fractional plant
// P = s^-0.5 G (sim/linear/ipmc_link_model.h, LinkResponseExact). Prints the
// gain crossover, phase margin and gain margin (or "no finite gain
// margin") of L, searched over [1e-4, 1e5] rad/s (ComputeMargins'
// defaults), and the controller's and the plant's gain and phase at the
// reference model's crossover, 5 rad/s. Controllers:
//  - pid: Kp + Ki/s + Kd s (eq. 10; defaults eq. 12, ideal derivative);
//  - fractional: K / s^lambda, exact (eq. 13; defaults eq. 14);
//  - fractional-oustaloup: K / s^lambda through its Oustaloup realisation
//    (--oustaloup-pairs N on a band; defaults N = 4 on [1e-3, 1e2] rad/s, as eq. 15);
//  - fractional-eq15: the paper's printed eq. 15, a ratio of quartics;
//  - none: C = 1 (the plant alone).
// --out DIR (with one link) writes DIR/bode.csv on the --w-min-rad-s..--w-max-rad-s grid: w_rad_s and
// dB/deg pairs for the plant, the controller, the open loop and the
// reference model's open loop (5/s)^1.16 (eq. 8). Phases are unwrapped
// along increasing w; DIR/bode.json names the curves.
//
// The options are the table BodeOptions() / StepOptions() of
// sim/identify/loop_analysis.h, which the Python module reads too; the
// computation, its checks and the files are RunBodeCommand /
// RunStepCommand there. Nothing is written unless the whole analysis
// succeeded.
#pragma once

#include <CLI/CLI.hpp>

#include "sim/cli/option_flags.h"
#include "sim/identify/loop_analysis.h"

namespace ipmc {

using BodeArgs = TableCommand<BodeCommand>;

// Adds subcommand "bode" to app, storing its options in args.
void AddBodeCommand(CLI::App& app, BodeArgs& args);

// Runs it and prints, if the command line chose it; returns its exit code,
// or -1 if it was not chosen. Throws FieldError (with the flag in place of
// the field) for bad options and std::runtime_error for output failures.
int RunBodeCommandLine(const BodeArgs& args);

}  // namespace ipmc
