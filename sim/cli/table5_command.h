// ipmc-swim table5: the paper's Table 5 (section 5.3), the tracking
// indices of every link under both controllers, reproduced and set beside
// the paper's values.
//
//   ipmc-swim table5 [--plants uniform|table2] [--cycles N]
//                    [--start-ramp-cycles X] [--loop multibody|transfer-function]
//                    [--jobs 1|2] [--out DIR]
//
// The experiment, its readings, its options (Table5Options()) and its
// files (RunTable5Command) are sim/runs/table5_run.h; this prints the
// table. A bad option value is one line naming the option and its allowed
// range, a non-zero exit code and no files.
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
