// A scenario with some of its keys replaced: the scenario file (the base)
// with overrides, as `run --set`, a sweep's [set], [grid] and [[point]]
// and the Python module's keyword overrides give them.
//
// Keys are the scenario's dotted keys ("controller.kp", "waveform.alpha",
// ...); a nested table stands for the dotted keys under it. An override
// replaces the value in the base's TOML (adding the key, and its table, if
// the base lacks it); the result is serialised and read by ParseScenario
// with the base's path as source, so every key and check of scenario
// files applies and relative paths resolve as in the base. An override
// that changes a table's kind (controller.kind, waveform.kind) drops the
// base's keys that belong only to the other kind; keys of the other kind
// given as overrides stay errors. The scenario reader's errors are moved
// to where their key came from: the override's line in `source`, else the
// key's line in the base.
#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sim/base/error.h"
#include "sim/core/scenario.h"

namespace ipmc {

// One replaced (or added) key of the base scenario.
struct ScenarioOverride {
  std::string key;                // dotted: "waveform.frequency_Hz"
  std::vector<std::string> path;  // {"waveform", "frequency_Hz"}
  const toml::node* value = nullptr;
  std::uint32_t line = 0, column = 0;  // in the overrides' source
};

// In the order the overrides' source gives them.
inline bool OverrideBefore(const ScenarioOverride& a, const ScenarioOverride& b) {
  return a.line != b.line ? a.line < b.line : a.column < b.column;
}

// The outcome of reading the base with overrides.
struct OverriddenScenario {
  std::optional<ScenarioConfig> scenario;
  std::string error;                  // relocated: names the overrides' source or the base
  std::optional<InputError> failure;  // the same error with its parts
  // An unknown or ill-typed override, which stops the sweep.
  std::optional<InputError> fatal;
  std::string text;  // the TOML read
};

// Reads overrides from `source` (a sweep file, "--set", ...) onto a base.
class ScenarioOverrides {
 public:
  explicit ScenarioOverrides(std::string source) : source_(std::move(source)) {}
  virtual ~ScenarioOverrides() = default;

  // The scenario file the overrides apply to, read and checked to be a
  // scenario by itself; "": none (the overrides are the whole scenario and
  // relative paths resolve from the working directory).
  void LoadBase(const std::string& base_path);
  const std::string& base_path() const { return base_path_; }

  // An error in the overrides' source itself, at `line` (0: none), about `key`.
  [[noreturn]] void Fail(std::uint32_t line, const std::string& message,
                         InputProblem problem = InputProblem::kBadValue,
                         const std::string& key = "") const {
    throw InputError(problem, {source_, line}, key, message);
  }

  // The override of dotted key `name`, declared by `key`.
  ScenarioOverride OverrideAt(const std::string& name, const toml::key& key,
                              const toml::node* value) const;
  // Every value under `table` as an override (nested tables stand for the
  // dotted keys under them).
  void FlattenOverrides(const toml::table& table, const std::string& prefix,
                        std::vector<ScenarioOverride>* overrides) const;
  // A key given twice, or a key inside another given key (which would
  // replace it), is an error.
  void RejectRepeatedKeys(std::vector<const ScenarioOverride*> overrides) const;
  // The base with `overrides`, read by ParseScenario, its errors relocated.
  OverriddenScenario ReadScenario(const std::vector<const ScenarioOverride*>& overrides) const;

 protected:
  std::string source_;
  std::string base_path_;
  toml::table base_;

 private:
  std::vector<std::string> SplitKey(const std::string& key, std::uint32_t line) const;
  toml::table WithOverrides(const std::vector<const ScenarioOverride*>& overrides) const;
  struct ErrorOrigin;
  ErrorOrigin Locate(const InputError& error,
                     const std::vector<const ScenarioOverride*>& overrides) const;
};

// Calls leaf(dotted name, key, value) for every value under `table` that
// is not a table, a nested table standing for the dotted keys under it.
template <typename Leaf>
void ForEachLeaf(const toml::table& table, const std::string& prefix, const Leaf& leaf) {
  for (auto&& [key, node] : table) {
    const std::string name = prefix + std::string(key.str());
    if (const toml::table* nested = node.as_table()) {
      ForEachLeaf(*nested, name + ".", leaf);
    } else {
      leaf(name, key, node);
    }
  }
}

// The scenario file `base_path` with `overrides` applied as a sweep's
// [set] applies them. With an empty base_path the overrides are the whole
// scenario. Throws InputError with one line: errors in the base name the
// base file and line, errors in an override `source`, the override's line
// and the key.
ScenarioConfig ScenarioWithOverrides(const std::string& base_path, const toml::table& overrides,
                                     const std::string& source);

// One scenario key set on a command line: the option as typed ("--set
// cycles=2", "--cycles 2") and the KEY=VALUE it stands for (VALUE in TOML).
struct ScenarioSetting {
  std::string option;
  std::string assignment;
};
// The setting of `run --set KEY=VALUE`; throws FieldError naming --set
// unless `key_value` is KEY=VALUE on one line.
ScenarioSetting SetOption(const std::string& command, const std::string& key_value);
// The scenario file with the settings applied in order (ScenarioWithOverrides,
// one override per setting). An error in a setting throws FieldError
// "COMMAND: OPTION: message", naming the option (and, for a TOML syntax
// error, how to quote a string VALUE); errors in the file stay InputError.
ScenarioConfig ScenarioWithSettings(const std::string& command, const std::string& scenario_path,
                                    const std::vector<ScenarioSetting>& settings);

}  // namespace ipmc
