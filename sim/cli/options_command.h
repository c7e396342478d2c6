// ipmc-swim options: the option reference, every command's option table
// (sim/io/option_table.h) with each option's name (the Python keyword),
// flag, type, unit, allowed values, default and meaning.
//
//   ipmc-swim options [--format text|markdown]
//
// text (default) for reading at a terminal; markdown is docs/OPTIONS.md,
// which a test compares with this output.
#pragma once

#include <CLI/CLI.hpp>

#include "sim/cli/option_flags.h"

namespace ipmc {

// The table is OptionsOptions() (sim/io/option_table.h).
using OptionsArgs = TableCommand<ReferenceCommand>;

void AddOptionsCommand(CLI::App& app, OptionsArgs& args);

// Prints the reference if `options` was chosen; -1 if not.
int RunOptionsCommandLine(const OptionsArgs& args);

}  // namespace ipmc
