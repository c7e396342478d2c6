// ipmc-swim export: a scenario's controllers as C99, JSON and CSV for a
// processor's fixed-rate loop (sim/identify/controller_export.h, where the
// options table ExportOptions() and the files are; the Python module's
// export reads the same table).
#pragma once

#include <CLI/CLI.hpp>

#include "sim/cli/option_flags.h"
#include "sim/identify/controller_export.h"

namespace ipmc {

using ExportArgs = TableCommand<ExportCommand>;

// Adds subcommand "export" to app, storing its options in args.
void AddExportCommand(CLI::App& app, ExportArgs& args);

// Runs it and prints the files written, if the command line chose it;
// returns its exit code, or -1 if it was not chosen.
int RunExportCommandLine(const ExportArgs& args);

}  // namespace ipmc
