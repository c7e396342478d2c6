// ipmc-swim resistance MODEL.xml [--fluid ...] [--out R.json]: the 6 x 6
// resistance of the model held rigid (sim/core/resistance_command.h),
// printed with Purcell's propulsion matrix for --axis.
#pragma once

#include <CLI/CLI.hpp>

#include "sim/cli/option_flags.h"
#include "sim/core/resistance_command.h"

namespace ipmc {

using ResistanceArgs = TableCommand<ResistanceCommand>;

// Adds subcommand "resistance" to app, storing its options in args.
void AddResistanceCommand(CLI::App& app, ResistanceArgs& args);

// Runs it and prints R, if the command line chose it; returns its exit
// code, or -1 if it was not chosen.
int RunResistanceCommandLine(const ResistanceArgs& args);

}  // namespace ipmc
