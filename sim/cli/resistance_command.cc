#include "sim/cli/resistance_command.h"

#include <iostream>

namespace ipmc {

void AddResistanceCommand(CLI::App& app, ResistanceArgs& args) {
  AddTableCommand(app, ResistanceOptions(), args);
}

int RunResistanceCommandLine(const ResistanceArgs& args) {
  if (!args.Chosen()) return -1;
  const ResistanceOutcome outcome = TranslatingFieldErrors(
      ResistanceOptions(), [&] { return RunResistanceCommand(args.spec); });
  std::cout << ResistanceText(args.spec, outcome);
  return 0;
}

}  // namespace ipmc
