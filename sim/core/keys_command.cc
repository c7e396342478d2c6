#include "sim/core/keys_command.h"

#include "plugin/base/error.h"
#include "sim/core/scenario_keys.h"

namespace ipmc {

const OptionTable<ReferenceCommand>& KeysOptions() {
  static const OptionTable<ReferenceCommand> table = ReferenceOptions(
      "keys", "Print every scenario and sweep-file key: type, unit, range, default, meaning",
      "docs/SCENARIO_KEYS.md");
  return table;
}

void CheckReferenceFormat(const std::string& command, const ReferenceCommand& reference) {
  if (reference.format != "text" && reference.format != "markdown") {
    throw FieldError(command + ": format must be text or markdown (got '" + reference.format + "')",
                     "format", "text | markdown");
  }
}

std::string KeysReference(const ReferenceCommand& command) {
  CheckReferenceFormat("keys", command);
  return KeyReference(command.format == "markdown" ? KeyFormat::kMarkdown : KeyFormat::kText);
}

}  // namespace ipmc
