// ipmc-swim identify: frequency response (Welch) and Levy fits of G1 and
// G2 from bench data (paper sections 4.1, 4.2).
//
//   ipmc-swim identify DATA.csv --input voltage1_V --output relative3_mm
//       [--sample-rate-hz 1000] [--band-rad-s 0.2,50] [--out DIR]
// DATA.csv: a header row naming the columns (the bench CSV: time_s,
// voltage1_V, relative1_mm, tip1_lateral_mm, free1_mm, voltage2_V, ...),
// then one row of numbers per sample. The two named columns are the input
// [V] and the output [mm]; if a time_s column is present its spacing must
// agree with --sample-rate-hz (0.1 %). Prints the Welch set-up, the G1 and
// G2 fits (P = s^-0.5 G) and Table 3's indices. --out DIR writes
// DIR/response.csv (w_rad_s, frequency_Hz, coherence, measured re/im,
// measured, P1 and P2 in dB and unwrapped deg, in_band) and
// DIR/identification.json (the parameters and indices).
//
// The options are the table IdentifyOptions() of
// sim/identify/identify_run.h, which the Python module reads too; the
// computation, its checks and its files are RunIdentifyCommand there.
// Nothing is written unless the command succeeded, and each file is
// written atomically.
#pragma once

#include <CLI/CLI.hpp>

#include "sim/cli/option_flags.h"
#include "sim/identify/identify_run.h"

namespace ipmc {

using IdentifyArgs = TableCommand<IdentifyCommand>;

// Adds subcommand "identify" to app, storing its options in args.
void AddIdentifyCommand(CLI::App& app, IdentifyArgs& args);

// Runs it and prints, if the command line chose it; returns its exit code,
// or -1 if it was not chosen. Throws FieldError (with the flag in place of
// the field) for bad options, InputError for bad data and
// std::runtime_error for simulation or output failures.
int RunIdentifyCommandLine(const IdentifyArgs& args);

}  // namespace ipmc
