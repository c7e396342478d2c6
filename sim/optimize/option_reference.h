// `options`: the reference of every command's option table (the name,
// which is the Python keyword, the flag, type, unit, allowed values,
// default and meaning), as `ipmc-swim options` prints it and
// ipmc_swim.options() returns it; --format markdown is docs/OPTIONS.md.
#pragma once

#include <string>
#include <vector>

#include "sim/io/option_table.h"

namespace ipmc {

// Every command's table, in the reference's order.
std::vector<OptionTableInfo> EveryOptionTable();

// The reference in command.format ("text" or "markdown").
std::string OptionsReference(const ReferenceCommand& command);

}  // namespace ipmc
