// Every command's option table (sim/io/option_table.h), in the order of
// `ipmc-swim options` and docs/OPTIONS.md: the one list that the options
// command prints and the tests check against the naming convention. A new
// command's table is one line in CommandOptionTables (option_tables.cc).
#pragma once

#include <string>
#include <vector>

#include "sim/io/option_table.h"

namespace ipmc {

std::vector<OptionTableInfo> CommandOptionTables();

// The reference of every table, "text" or "markdown" (docs/OPTIONS.md):
// what `ipmc-swim options --format FORMAT` prints.
std::string CommandOptionReference(const std::string& format);

}  // namespace ipmc
