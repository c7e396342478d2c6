// ipmc-swim generate: the MJCF of an N-link flagellum
// (sim/core/model_generator.h), to a file or to stdout. The options are
// the table GenerateOptions() of sim/core/generate_command.h, the fields
// of FlagellumSpec, which the Python module's generate_model reads too.
#pragma once

#include <CLI/CLI.hpp>

#include "sim/cli/option_flags.h"
#include "sim/core/generate_command.h"

namespace ipmc {

using GenerateArgs = TableCommand<GenerateCommand>;

// Adds subcommand "generate" to app, storing its options in args.
void AddGenerateCommand(CLI::App& app, GenerateArgs& args);

// Runs it (printing the MJCF unless --out), if the command line chose it;
// returns its exit code, or -1 if it was not chosen.
int RunGenerateCommandLine(const GenerateArgs& args);

}  // namespace ipmc
