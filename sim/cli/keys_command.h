// ipmc-swim keys: the key reference (sim/core/scenario_keys.h), every
// scenario key and sweep-file key with its type, unit, allowed range,
// default and meaning; its option table is sim/core/keys_command.h.
//
//   ipmc-swim keys [--format text|markdown]
//
// text (default) for reading at a terminal; markdown is
// docs/SCENARIO_KEYS.md, which a test compares with this output.
#pragma once

#include <CLI/CLI.hpp>

#include "sim/cli/option_flags.h"
#include "sim/core/keys_command.h"

namespace ipmc {

using KeysArgs = TableCommand<ReferenceCommand>;

void AddKeysCommand(CLI::App& app, KeysArgs& args);

// Prints the reference if `keys` was chosen; -1 if not.
int RunKeysCommandLine(const KeysArgs& args);

}  // namespace ipmc
