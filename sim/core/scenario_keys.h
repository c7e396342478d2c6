// The key reference: one table of every scenario key and every sweep-file
// key, with its type, unit, allowed range, default and meaning, and for a
// scenario key how it is read into a ScenarioConfig and written back from
// one. The scenario reader (sim/core/scenario.cc) takes from it the keys
// each table allows, the choices of every string key, the bounds of every
// number, which kind of a table a key belongs to, and each key's reading;
// ResolvedScenarioToml takes each key's value from it; the sweep reader
// (sim/batch/sweep_file.cc) takes the keys of a sweep file; `ipmc-swim
// keys` prints it and docs/SCENARIO_KEYS.md is its Markdown form. Tests read every entry back through the parser: its
// default is accepted and gives the scenario of no key, its refused value
// is refused naming the key.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sim/base/error.h"

namespace ipmc {

struct ScenarioConfig;  // sim/core/scenario.h

// Keys and tables the reader's checks across keys name.
constexpr char kIncludeKey[] = "include";
constexpr char kModelKey[] = "model";
constexpr char kLinkLengthsKey[] = "link_lengths_mm";
constexpr char kTimestepKey[] = "timestep_s";
constexpr char kSampleRateKey[] = "controller.sample_rate_Hz";
constexpr char kControllerTable[] = "controller";
constexpr char kWaveformTable[] = "waveform";
constexpr char kDriveModeKey[] = "drive.mode";
constexpr char kDriveCsvKey[] = "drive.csv";

// A key's value in a scenario document, checked as it is taken: every
// failure throws InputError naming the source, the line and the key.
class KeyValue {
 public:
  virtual ~KeyValue() = default;
  virtual const std::string& name() const = 0;    // "controller.kp"
  virtual const std::string& source() const = 0;  // the scenario file
  virtual double Number() const = 0;              // finite, within the key's bounds
  virtual int Integer() const = 0;                // within the key's bounds
  virtual bool Boolean() const = 0;
  virtual std::string String() const = 0;
  virtual std::string Choice() const = 0;  // one of the key's choices
  // The size of an array (else a type error: must be `expected`), and its
  // element `index` as a number within the key's bounds.
  virtual std::size_t ArraySize(const std::string& expected) const = 0;
  virtual double NumberAt(std::size_t index) const = 0;
  [[noreturn]] virtual void Fail(const std::string& message, const std::string& allowed,
                                 InputProblem problem = InputProblem::kBadValue) const = 0;
};

// Sets the fields of `config` the key stands for.
using KeyReader = std::function<void(const KeyValue& value, ScenarioConfig& config)>;
// The key's value in `config` as TOML; nullopt where a resolved scenario
// leaves it out (the model file gives it).
using KeyWriter = std::function<std::optional<std::string>(const ScenarioConfig& config)>;

// A key that applies only when another key of its table (its selector, a
// kChoice key: "controller.kind") has `value`.
struct KeyCondition {
  const char* selector;
  const char* value;
};

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
  std::string name;     // dotted: "controller.kp"
  KeyType type;
  const char* unit;     // "" for none
  std::string allowed;  // the allowed range or values, as messages state it
  std::string default_text;  // the default as documented (a TOML value or words)
  std::string meaning;
  // A TOML value equal to the default ("" if the default is not a value,
  // e.g. the model's own): reading it gives the scenario of no key.
  std::string default_toml;
  // Another accepted value ("" if default_toml serves).
  std::string example_toml;
  // A value of the right type that is refused naming the key ("" if
  // every value of the type is allowed).
  std::string refused_toml;
  // The selectors' values the key applies under, checked in order (a
  // fractional integrator's gain: controller.kind = "fractional", then
  // controller.realisation = "oustaloup").
  std::vector<KeyCondition> only;
  // TOML lines selecting the kind of table the key belongs to
  // ("controller.kind = \"fractional\""), from `only` where a selector's
  // value is not its default; "" if it applies by default.
  std::string applies_when;
  // kChoice: "pid|fractional", from the choice's table (sim/core/choice_table.h)
  // or, for a choice the plugin parses, as the plugin spells it.
  std::string choices;
  // Bounds of numbers (each element of a kNumberArray), checked by
  // NumberOutOfRange / IntegerOutOfRange; kNone: unbounded there, or checked by a Config's Validate()
  // (the allowed text states it).
  Bound lower = Bound::kNone;
  double minimum = 0.0;
  Bound upper = Bound::kNone;
  double maximum = 0.0;
  // The Config fields whose Validate() errors are this key's (space
  // separated; "": the key's last name part, "c0_um").
  const char* fields = "";
  // Scenario keys: how the key is read and written (nullptr: the reader
  // does not read it / a resolved scenario leaves it out).
  KeyReader read;
  KeyWriter write;
};

// Scenario keys, in the order the reader lists them.
const std::vector<KeySpec>& ScenarioKeys();
// Sweep-file keys (sim/batch/sweep_file.h).
const std::vector<KeySpec>& SweepFileKeys();

// The scenario key called `name` (dotted), or nullptr.
const KeySpec* FindScenarioKey(std::string_view name);
// The keys a scenario table allows, in table order: for "" the top-level
// keys and tables ("model", ..., "controller", ...), for "controller" the
// keys under it ("kind", "sample_rate_Hz", ...).
std::vector<std::string> ScenarioKeysUnder(std::string_view table);
// Whether `key` answers for the Config field `field` (KeySpec::fields).
bool KeyHasField(const KeySpec& key, const std::string& field);
// Whether some key applies only under a value of `key`.
bool IsKeySelector(const KeySpec& key);
// The value of a selector (a kChoice key) in `config`: "pid".
std::string SelectorValue(const std::string& selector, const ScenarioConfig& config);
// Whether every condition of `key` holds in `config`; else the first that
// does not.
const KeyCondition* FailedCondition(const KeySpec& key, const ScenarioConfig& config);
// The choices of a kChoice key.
std::vector<std::string> KeyChoices(const KeySpec& key);
// The choices as a message states them: "\"rft\" or \"stokeslets\"".
std::string QuotedChoices(const std::vector<std::string>& choices);

// A value outside its key's range: the one-line message ("NAME must be >=
// 0 (got -1)") and the allowed range (">= 0").
struct KeyRangeError {
  std::string message;
  std::string allowed;
};
// The range check of every reader (scenario files, and so sweeps and
// --set, and optimisation designs): a number must be finite and within
// the key's bounds (each element of a kNumberArray); `name` is what the
// message calls it ("controller.kp", "link_lengths_mm[1]").
std::optional<KeyRangeError> NumberOutOfRange(const KeySpec& key, const std::string& name,
                                              double value);
// The same for an integer key, its bounds and value written as integers.
std::optional<KeyRangeError> IntegerOutOfRange(const KeySpec& key, const std::string& name,
                                               long long value);
std::string KeyTypeName(KeyType type);

}  // namespace ipmc
