#include "sim/cli/keys_command.h"

#include <cstdio>
#include <string>

namespace ipmc {

void AddKeysCommand(CLI::App& app, KeysArgs& args) { AddTableCommand(app, KeysOptions(), args); }

int RunKeysCommandLine(const KeysArgs& args) {
  if (!args.Chosen()) return -1;
  const std::string reference = KeysReference(args.spec);
  std::fwrite(reference.data(), 1, reference.size(), stdout);
  return 0;
}

}  // namespace ipmc
