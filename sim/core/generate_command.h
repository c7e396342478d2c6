// `generate` as both front ends run it (sim/core/model_generator.h): the
// option table of the flagellum's fields and the output file.
#pragma once

#include <string>

#include "sim/core/model_generator.h"
#include "sim/io/option_table.h"

namespace ipmc {

struct GenerateCommand : FlagellumSpec {
  std::string out;  // "": none (the command line prints the MJCF)
};

const OptionTable<GenerateCommand>& GenerateOptions();

// Validates (FlagellumSpec::Validate), generates and writes `out` (if set)
// atomically; returns the MJCF text.
std::string RunGenerateCommand(const GenerateCommand& command);

}  // namespace ipmc
