// ipmc-swim pipeline: bench chirp, identification and design on the
// simulated flagellum, as a report.
//
//   ipmc-swim pipeline [--out DIR] [--duration-s 200] [--repeats 1]
//       [--noise-mm 0] [--drive each|first] [--model M] ...
// The bench chirp of section 4.1 (3 V, 0.1 to 200 Hz, 1 kHz) on the
// simulated clamped flagellum, then Welch, Levy and both designs for link
// 3 on its identified G1. --drive each (default) drives each link in turn
// (three runs, in parallel threads) and identifies its relative tip
// deflection L_q sin(theta_q), so that every identified model can be
// compared with the parameters the simulator was given; --drive first is
// the paper's experiment: link 1 alone is driven and each link's tip is
// measured laterally (the laser). The simulator is deterministic, so
// --repeats R records differ only by the added measurement noise (white,
// Gaussian, --noise-mm standard deviation, seeded by --seed); the Welch
// spectra of the R records are pooled. If the record is too short for the
// band's low end, the band starts at the first Welch bin (said in the
// report). Prints the Markdown report; --out DIR also writes
// DIR/report.md and DIR/response_link<q>.csv.
//
// The options are the table PipelineOptions() of
// sim/identify/pipeline_run.h, which the reference documents; the
// computation, its checks and its files are RunPipelineCommand there.
// Nothing is written unless the command succeeded, and each file is
// written atomically.
#pragma once

#include <CLI/CLI.hpp>

#include "sim/cli/option_flags.h"
#include "sim/identify/pipeline_run.h"

namespace ipmc {

using PipelineArgs = TableCommand<PipelineCommand>;

// Adds subcommand "pipeline" to app, storing its options in args.
void AddPipelineCommand(CLI::App& app, PipelineArgs& args);

// Runs it and prints, if the command line chose it; returns its exit code,
// or -1 if it was not chosen. Throws FieldError (with the flag in place of
// the field) for bad options, InputError for bad data and
// std::runtime_error for simulation or output failures.
int RunPipelineCommandLine(const PipelineArgs& args);

}  // namespace ipmc
