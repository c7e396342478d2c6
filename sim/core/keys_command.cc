#include "sim/core/keys_command.h"

#include "sim/core/scenario_keys.h"

namespace ipmc {

const OptionTable<ReferenceCommand>& KeysOptions() {
  static const OptionTable<ReferenceCommand> table = ReferenceOptions(
      "keys", "Print every scenario and sweep-file key: type, unit, range, default, meaning",
      "docs/SCENARIO_KEYS.md");
  return table;
}

std::string KeysReference(const ReferenceCommand& command) {
  return KeyReference(command.format == "markdown" ? KeyFormat::kMarkdown : KeyFormat::kText);
}

}  // namespace ipmc
