#include "sim/cli/keys_command.h"

#include <cstdio>

#include "sim/cli/command.h"
#include "sim/core/scenario_keys.h"

namespace ipmc {
namespace {

constexpr char kCommand[] = "keys";

}  // namespace

void AddKeysCommand(CLI::App& app, KeysArgs& args) {
  CLI::App* cmd = AddCommand(app, kCommand,
                             "Print every scenario and sweep-file key: type, unit, range, "
                             "default, meaning");
  cmd->add_option("--format", args.format, "text | markdown (docs/SCENARIO_KEYS.md)")
      ->check(CLI::IsMember({"text", "markdown"}));
}

int RunKeysCommand(const CLI::App& app, const KeysArgs& args) {
  if (!app.got_subcommand(kCommand)) return -1;
  const std::string reference =
      KeyReference(args.format == "markdown" ? KeyFormat::kMarkdown : KeyFormat::kText);
  std::fwrite(reference.data(), 1, reference.size(), stdout);
  return 0;
}

}  // namespace ipmc
