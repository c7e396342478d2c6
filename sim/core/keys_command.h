// `keys`: the reference of every scenario and sweep-file key
// (sim/core/scenario_keys.h), as text or as docs/SCENARIO_KEYS.md.
#pragma once

#include <string>

#include "sim/io/option_table.h"

namespace ipmc {

const OptionTable<ReferenceCommand>& KeysOptions();

enum class KeyFormat { kText, kMarkdown };
// The whole reference (scenario keys, then sweep-file keys), as
// `ipmc-swim keys` prints it; kMarkdown is docs/SCENARIO_KEYS.md.
std::string KeyReference(KeyFormat format);

// The reference in command.format.
std::string KeysReference(const ReferenceCommand& command);

// Throws FieldError naming format unless it is "text" or "markdown" (the
// command line's flag checks it too; Python's keyword is checked here).
void CheckReferenceFormat(const std::string& command, const ReferenceCommand& reference);

}  // namespace ipmc
