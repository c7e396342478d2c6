// The key reference: one table of every scenario key and every sweep-file
// key, with its type, unit, allowed range, default and meaning. The
// scenario reader (sim/core/scenario.cc) takes from it the keys each table
// allows, the choices of every string key and the bounds of every number
// it checks; the sweep reader (sim/batch/sweep.cc) takes the keys of a
// sweep file; `ipmc-swim keys` prints it and docs/SCENARIO_KEYS.md is its
// Markdown form. Tests read every entry back through the parser: its
// default is accepted and gives the scenario of no key, its refused value
// is refused naming the key.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace ipmc {

enum class KeyType {
  kString,
  kChoice,       // a string, one of KeySpec::choices
  kBoolean,
  kInteger,
  kNumber,       // a finite number; integers are accepted
  kNumberArray,  // an array of finite numbers
  kTable,        // sweep files: a table of scenario keys
  kTableArray,   // sweep files: an array of tables ([[point]])
};

// A side of a number's range the reader checks from the table.
enum class Bound { kNone, kClosed, kOpen };

struct KeySpec {
  const char* name;     // dotted: "controller.kp"
  KeyType type;
  const char* unit;     // "" for none
  const char* allowed;  // the allowed range or values, as messages state it
  const char* default_text;  // the default as documented (a TOML value or words)
  const char* meaning;
  // A TOML value equal to the default ("" if the default is not a value,
  // e.g. the model's own): reading it gives the scenario of no key.
  const char* default_toml = "";
  // Another accepted value ("" if default_toml serves).
  const char* example_toml = "";
  // A value of the right type that is refused naming the key ("" if
  // every value of the type is allowed).
  const char* refused_toml = "";
  // TOML lines selecting the kind of table the key belongs to
  // ("controller.kind = \"fractional\""); "" if it always applies.
  const char* applies_when = "";
  const char* choices = "";  // kChoice: "pid|fractional"
  // Bounds of numbers (each element of a kNumberArray), checked by the
  // reader; kNone: unbounded there, or checked by a Config's Validate()
  // (the allowed text states it).
  Bound lower = Bound::kNone;
  double minimum = 0.0;
  Bound upper = Bound::kNone;
  double maximum = 0.0;
};

// Scenario keys, in the order the reader lists them.
const std::vector<KeySpec>& ScenarioKeys();
// Sweep-file keys (sim/batch/sweep.h).
const std::vector<KeySpec>& SweepFileKeys();

// The scenario key called `name` (dotted), or nullptr.
const KeySpec* FindScenarioKey(std::string_view name);
// The keys a scenario table allows, in table order: for "" the top-level
// keys and tables ("model", ..., "controller", ...), for "controller" the
// keys under it ("kind", "sample_rate_Hz", ...).
std::vector<std::string> ScenarioKeysUnder(std::string_view table);
// The choices of a kChoice key.
std::vector<std::string> KeyChoices(const KeySpec& key);
std::string KeyTypeName(KeyType type);

enum class KeyFormat { kText, kMarkdown };
// The whole reference (scenario keys, then sweep-file keys), as
// `ipmc-swim keys` prints it; kMarkdown is docs/SCENARIO_KEYS.md.
std::string KeyReference(KeyFormat format);

}  // namespace ipmc
