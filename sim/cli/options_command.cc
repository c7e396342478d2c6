#include "sim/cli/options_command.h"

#include <cstdio>
#include <string>

#include "sim/optimize/option_reference.h"

namespace ipmc {

void AddOptionsCommand(CLI::App& app, OptionsArgs& args) {
  AddTableCommand(app, OptionsOptions(), args);
}

int RunOptionsCommandLine(const OptionsArgs& args) {
  if (!args.Chosen()) return -1;
  const std::string reference = OptionsReference(args.spec);
  std::fwrite(reference.data(), 1, reference.size(), stdout);
  return 0;
}

}  // namespace ipmc
