// ipmc-swim keys: the key reference (sim/core/scenario_keys.h), every
// scenario key and sweep-file key with its type, unit, allowed range,
// default and meaning.
//
//   ipmc-swim keys [--format text|markdown]
//
// text (default) for reading at a terminal; markdown is
// docs/SCENARIO_KEYS.md, which a test compares with this output.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace ipmc {

struct KeysArgs {
  std::string format = "text";
};

// Adds subcommand "keys" to app, storing options in args.
void AddKeysCommand(CLI::App& app, KeysArgs& args);

// Prints the reference if app parsed "keys"; returns its exit code, or -1
// if it was not chosen.
int RunKeysCommand(const CLI::App& app, const KeysArgs& args);

}  // namespace ipmc
