// ipmc-swim step: the closed loop of each link in the time domain (paper section 5.2).
//
//   ipmc-swim step --controller pid|fractional [--links 1,2,3] ...
// Unit step (1 mm) of each link's closed loop (unity feedback, controller
// sampled at --sample-rate-hz, clamped to +-v_max_V unless --no-clamp; see
// controllers/closed_loop.h). The plant's s^-0.5 is realised accurately by
// 20 Oustaloup pairs on [1e-5, 1e5] rad/s, and so is the fractional
// controller's s^-lambda. Prints per link the overshoot, 10-90 % rise
// time, peak, 2 % settling time, largest |u| and J of eq. 11 against the
// reference model over the horizon (--horizon-s, 10 s by default), and the
// reference model's own step metrics. The step metrics must not depend on
// where the record stops: each link's simulation goes on past the
// horizon, a horizon at a time, until its metrics are determined
// (controllers/closed_loop.h, CheckStepRecord: 90 % reached, the peak
// passed, inside the settling band for at least half the record), at most
// to --max-horizon-s (300 s) and 1e6 samples; the record's length is
// printed (record_s), and a metric it still does not determine is marked
// '*' and named below the table. --out DIR writes DIR/step.csv over the
// horizon: time_s, reference_model, then y_link<q> [mm] and u_link<q> [V]
// for each link, and DIR/step.json the controller and clamp.
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

using StepArgs = TableCommand<StepCommand>;

// Adds subcommand "step" to app, storing its options in args.
void AddStepCommand(CLI::App& app, StepArgs& args);

// Runs it and prints, if the command line chose it; returns its exit code,
// or -1 if it was not chosen. Throws FieldError (with the flag in place of
// the field) for bad options and std::runtime_error for output failures.
int RunStepCommandLine(const StepArgs& args);

}  // namespace ipmc
