#include "sim/cli/generate_command.h"

#include <iostream>
#include <string>

namespace ipmc {

void AddGenerateCommand(CLI::App& app, GenerateArgs& args) {
  AddTableCommand(app, GenerateOptions(), args);
}

int RunGenerateCommandLine(const GenerateArgs& args) {
  if (!args.Chosen()) return -1;
  const std::string xml =
      TranslatingFieldErrors(GenerateOptions(), [&] { return RunGenerateCommand(args.spec); });
  if (args.spec.out.empty()) std::cout << xml;
  return 0;
}

}  // namespace ipmc
