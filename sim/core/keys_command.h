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

}  // namespace ipmc
