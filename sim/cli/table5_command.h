// ipmc-swim table5: the paper's Table 5 (section 5.3), the tracking
// indices of every link under both controllers, reproduced and set beside
// the paper's values.
//
//   ipmc-swim table5 [--plants uniform|table2] [--cycles N]
//                    [--start-ramp-cycles X] [--loop multibody|transfer-function]
//                    [--jobs 1|2] [--out DIR]
//
// Both controllers run in the paper's linear loop (no clamp) on
// scenarios/paper.toml's setting (model, time step, waveform, sample rate,
// PID gains): C_I through eq. 15 as printed (controllers/paper_eq15.h;
// section 5.3: "the results of the non-integer order controller
// correspond to its approximation") and the PID of eq. 12. Per link, with
// e = r - y the error of the link's relative tip deflection [mm] over the
// horizon H of `cycles` wave periods (rectangle rule at the controller's
// sample rate, as `run` computes them):
//   IAE = int_0^H |e| dt [mm s],  ITAE = int_0^H t |e| dt [mm s^2],
// printed beside the paper's value with the relative error
// (here - paper) / paper.
//
// Readings the paper leaves open, as options:
//  - plants: uniform (every link eq. 7's plant, section 5.3's "same
//    dynamics"; default) or table2 (Table 2's row per link);
//  - cycles: the horizon in wave periods (default: the scenario's, 3);
//  - start-ramp-cycles: the references' fade-in (default: the scenario's
//    waveform.start_ramp_cycles, 0.25); 0 starts the references at their
//    t = 0 values, a step;
//  - loop: multibody (the MuJoCo run of `run`; default) or
//    transfer-function (each link's plant P_q(s) of the model, alone in
//    its loop: no body, drag or coupling between the links; the output is
//    the plant's free deflection, advanced exactly over each sample by
//    zero-order hold).
// With --jobs 2 (default) the two controllers run on two threads; each
// run owns its model, data and controller state, so the table does not
// depend on --jobs. --out DIR writes DIR/table5.csv and DIR/table5.json
// (each atomically) once both runs have succeeded. A bad option value is
// one line naming the option and its allowed range, a non-zero exit code
// and no files.
#pragma once

#include <CLI/CLI.hpp>

#include "sim/cli/option_flags.h"
#include "sim/runs/table5_run.h"

namespace ipmc {

using Table5Args = TableCommand<Table5Command>;

// Adds subcommand "table5" to app, storing its options in args.
void AddTable5Command(CLI::App& app, Table5Args& args);

// Runs it and prints, if the command line chose it; returns its exit code,
// or -1 if it was not chosen. Throws FieldError (with the flag in place of
// the field) for bad options and std::runtime_error for failing runs and
// output failures.
int RunTable5CommandLine(const Table5Args& args);

}  // namespace ipmc
