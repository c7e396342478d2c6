// ipmc-swim options: the option reference, every command's option table
// (sim/io/option_table.h) with each option's name (the Python keyword),
// flag, type, unit, allowed values, default and meaning.
//
//   ipmc-swim options [--format text|markdown]
//
// text (default) for reading at a terminal; markdown is docs/OPTIONS.md,
// which a test compares with this output.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace ipmc {

struct OptionsArgs {
  std::string format = "text";
};

// Adds subcommand "options" to app, storing options in args.
void AddOptionsCommand(CLI::App& app, OptionsArgs& args);

// Prints the reference if app parsed "options"; returns its exit code, or
// -1 if it was not chosen.
int RunOptionsCommand(const CLI::App& app, const OptionsArgs& args);

}  // namespace ipmc
