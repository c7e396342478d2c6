#include "sim/core/scenario_overrides.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstddef>
#include <sstream>
#include <utility>

#include "sim/io/files.h"
#include "sim/io/toml.h"

namespace ipmc {
namespace {

std::string TypeName(const toml::node& node) { return TomlTypeName(node.type()); }

// The table holding a dotted key, if the key is there, and its last part.
template <typename Table>
Table* ParentOf(Table* root, const std::string& dotted, std::string* last) {
  Table* table = root;
  std::string::size_type start = 0;
  for (;;) {
    const std::string::size_type dot = dotted.find('.', start);
    const std::string part = dotted.substr(start, dot == std::string::npos ? dot : dot - start);
    auto it = table->find(part);
    if (it == table->end()) return nullptr;
    if (dot == std::string::npos) {
      *last = part;
      return table;
    }
    table = it->second.as_table();
    if (table == nullptr) return nullptr;
    start = dot + 1;
  }
}

// The key at a dotted path of `root`, or nullptr.
const toml::key* FindKey(const toml::table& root, const std::string& dotted) {
  std::string last;
  const toml::table* parent = ParentOf(&root, dotted, &last);
  return parent == nullptr ? nullptr : &parent->find(last)->first;
}

// Removes the key at a dotted path of `root`; false if there is none.
bool EraseKey(toml::table* root, const std::string& dotted) {
  std::string last;
  toml::table* parent = ParentOf(root, dotted, &last);
  return parent != nullptr && parent->erase(last) > 0;
}

}  // namespace

// Where a scenario reader's error belongs.
struct ScenarioOverrides::ErrorOrigin {
  InputLocation where;        // the overrides' line or the base's
  bool in_overrides = false;  // the key is an override
  bool in_base = false;       // the key is the base's own
};

void ScenarioOverrides::LoadBase(const std::string& base_path) {
  base_path_ = base_path.empty() ? source_ : base_path;
  if (base_path.empty()) return;
  const std::string text = ReadTextFile(base_path_, "scenario file");
  base_ = ParseToml(text, base_path_);
  ParseScenario(text, base_path_);  // the base must be a scenario by itself
}

std::vector<std::string> ScenarioOverrides::SplitKey(const std::string& key,
                                                     std::uint32_t line) const {
  std::vector<std::string> path;
  std::string::size_type start = 0;
  for (;;) {
    const std::string::size_type dot = key.find('.', start);
    path.push_back(key.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
    if (path.back().empty()) Fail(line, "'" + key + "' is not a dotted scenario key");
    if (dot == std::string::npos) return path;
    start = dot + 1;
  }
}

ScenarioOverride ScenarioOverrides::OverrideAt(const std::string& name, const toml::key& key,
                                               const toml::node* value) const {
  ScenarioOverride entry;
  entry.key = name;
  entry.line = key.source().begin.line;
  entry.column = key.source().begin.column;
  entry.path = SplitKey(name, entry.line);
  entry.value = value;
  return entry;
}

void ScenarioOverrides::FlattenOverrides(const toml::table& table, const std::string& prefix,
                                         std::vector<ScenarioOverride>* overrides) const {
  ForEachLeaf(table, prefix,
              [&](const std::string& name, const toml::key& key, const toml::node& node) {
                overrides->push_back(OverrideAt(name, key, &node));
              });
}

// A key given twice, or a key inside another given key (which would
// replace it), is an error.
void ScenarioOverrides::RejectRepeatedKeys(std::vector<const ScenarioOverride*> overrides) const {
  std::sort(
      overrides.begin(), overrides.end(),
      [](const ScenarioOverride* a, const ScenarioOverride* b) { return OverrideBefore(*a, *b); });
  for (size_t i = 0; i < overrides.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      const ScenarioOverride& earlier = *overrides[j];
      const ScenarioOverride& later = *overrides[i];
      if (later.key == earlier.key) {
        Fail(later.line,
             later.key + " is given twice (also on line " + std::to_string(earlier.line) + ")");
      }
      for (const auto& [outer, inner] :
           {std::pair(&earlier, &later), std::pair(&later, &earlier)}) {
        if (inner->key.rfind(outer->key + ".", 0) == 0) {
          Fail(later.line, inner->key + " and " + outer->key + " (lines " +
                               std::to_string(earlier.line) + " and " + std::to_string(later.line) +
                               ") cannot both be given");
        }
      }
    }
  }
}

// The base with `overrides` inserted.
toml::table ScenarioOverrides::WithOverrides(
    const std::vector<const ScenarioOverride*>& overrides) const {
  toml::table root = base_;
  for (const ScenarioOverride* entry : overrides) {
    toml::table* table = &root;
    std::string parent;
    for (size_t i = 0; i + 1 < entry->path.size(); ++i) {
      parent += (i > 0 ? "." : "") + entry->path[i];
      auto it = table->find(entry->path[i]);
      if (it == table->end()) {
        it = table->insert(entry->path[i], toml::table{}).first;
      } else if (!it->second.is_table()) {
        Fail(entry->line, entry->key + ": " + parent + " is not a table in " + base_path_ +
                              " (it is a " + TypeName(it->second) + ")");
      }
      table = it->second.as_table();
    }
    table->insert_or_assign(entry->path.back(), *entry->value);
  }
  return root;
}

// The scenario reader's errors name lines of the serialised base with the
// overrides, which nobody has seen. Moves one to where its key came from:
// the override's line in the source (the key itself, or the first
// override under a table the error is about), else the key's line in the
// base; without a key, "BASE: ...". An error of another file, or a TOML
// syntax error (which cannot come from the serialised text), stays where
// it is.
ScenarioOverrides::ErrorOrigin ScenarioOverrides::Locate(
    const InputError& error, const std::vector<const ScenarioOverride*>& overrides) const {
  ErrorOrigin origin;
  origin.where = error.where();
  if (error.where().file != base_path_ || error.where().column > 0) return origin;
  origin.where = {base_path_};
  if (error.where().line == 0 || error.key().empty()) return origin;

  const ScenarioOverride* from = nullptr;
  for (const ScenarioOverride* entry : overrides) {
    if (entry->key == error.key()) from = entry;
  }
  for (const ScenarioOverride* entry : overrides) {
    if (from == nullptr && entry->key.rfind(error.key() + ".", 0) == 0) from = entry;
  }
  if (from != nullptr) {
    origin.in_overrides = true;
    origin.where = {source_, from->line};
  } else if (const toml::key* key = FindKey(base_, error.key())) {
    origin.in_base = true;
    origin.where = {base_path_, key->source().begin.line};
  }
  return origin;
}

OverriddenScenario ScenarioOverrides::ReadScenario(
    const std::vector<const ScenarioOverride*>& overrides) const {
  toml::table root = WithOverrides(overrides);
  OverriddenScenario point;
  for (;;) {
    std::ostringstream text;
    text << root;
    point.text = text.str();
    try {
      point.scenario = ParseScenario(text.str(), base_path_);
      return point;
    } catch (const InputError& failure) {
      const ErrorOrigin origin = Locate(failure, overrides);
      // A base key of the other kind of its table (the override changed
      // the kind): dropped, and read again.
      if (origin.in_base && failure.problem() == InputProblem::kOtherKind &&
          EraseKey(&root, failure.key())) {
        continue;
      }
      const InputError located(failure.problem(), origin.where, failure.key(), failure.message(),
                               failure.allowed());
      point.error = located.what();
      point.failure = located;
      const bool key_or_type = failure.problem() == InputProblem::kUnknownKey ||
                               failure.problem() == InputProblem::kWrongType;
      if (origin.in_overrides && key_or_type) point.fatal = located;
      return point;
    }
  }
}

ScenarioConfig ScenarioWithOverrides(const std::string& base_path, const toml::table& overrides,
                                     const std::string& source) {
  ScenarioOverrides reader(source);
  reader.LoadBase(base_path);
  std::vector<ScenarioOverride> entries;
  reader.FlattenOverrides(overrides, "", &entries);
  std::vector<const ScenarioOverride*> pointers;
  for (const ScenarioOverride& entry : entries) pointers.push_back(&entry);
  reader.RejectRepeatedKeys(pointers);
  OverriddenScenario point = reader.ReadScenario(pointers);
  if (!point.scenario) throw *point.failure;
  return std::move(*point.scenario);
}

ScenarioSetting SetOption(const std::string& command, const std::string& key_value) {
  const std::string::size_type equals = key_value.find('=');
  if (equals == std::string::npos || equals == 0 || key_value.find('\n') != std::string::npos) {
    ThrowOption(command, "--set", "KEY=VALUE (one line)", "'" + key_value + "'");
  }
  return {"--set " + key_value, key_value};
}

namespace {

std::string Trimmed(const std::string& text) {
  const std::string::size_type first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

// Whether a VALUE that TOML could not read is meant as a string: a bare
// word (letters first, then letters, digits, '_', '-', '.', '/'), which
// quoting makes a string. Numbers, arrays and the like are not.
bool LooksLikeBareWord(const std::string& value) {
  if (value.empty() || !std::isalpha(static_cast<unsigned char>(value.front()))) return false;
  if (value == "inf" || value == "nan" || value == "true" || value == "false") return false;
  return std::all_of(value.begin(), value.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' ||
           c == '/';
  });
}

// Checks what TOML would report less clearly, before parsing: an empty
// VALUE, a key set twice (or a key and a key inside it), a number beyond
// a double's range.
void CheckSettings(const std::string& command, const std::vector<ScenarioSetting>& settings) {
  const std::string allowed_value = "a TOML value: a number, true or false, a \"quoted string\"";
  std::vector<std::string> keys;
  for (const ScenarioSetting& setting : settings) {
    const std::string::size_type equals = setting.assignment.find('=');
    const std::string key = Trimmed(setting.assignment.substr(0, equals));
    const std::string value = Trimmed(setting.assignment.substr(equals + 1));
    const std::string option = setting.option.substr(0, setting.option.find(' '));
    if (value.empty()) {
      throw FieldError(command + ": " + setting.option + ": no value after '=' (give " +
                           allowed_value + ")",
                       option, allowed_value);
    }
    for (size_t k = 0; k < keys.size(); ++k) {
      const std::string& other = keys[k];
      const bool same = other == key;
      const bool nested = key.rfind(other + ".", 0) == 0 || other.rfind(key + ".", 0) == 0;
      if (same || nested) {
        throw FieldError(command + ": " + setting.option + ": " + key +
                             (same ? " is already set by " : " conflicts with ") +
                             settings[k].option + " (set each key once)",
                         option, "each key once");
      }
    }
    keys.push_back(key);
    const char first = value.front();
    if (std::isdigit(static_cast<unsigned char>(first)) || first == '-' || first == '+' ||
        first == '.') {
      errno = 0;
      char* end = nullptr;
      const double number = std::strtod(value.c_str(), &end);
      if (end == value.c_str() + value.size() && errno == ERANGE && std::isinf(number)) {
        throw FieldError(command + ": " + setting.option + ": " + value +
                             " is beyond the range of a number (at most about 1.8e308)",
                         option, "a finite number");
      }
    }
  }
}

}  // namespace

// The settings are one TOML document, line k the k-th setting, so that an
// error's line names the setting it came from.
ScenarioConfig ScenarioWithSettings(const std::string& command, const std::string& scenario_path,
                                    const std::vector<ScenarioSetting>& settings) {
  constexpr char kSource[] = "--set";
  CheckSettings(command, settings);
  std::string text;
  for (const ScenarioSetting& setting : settings) {
    const std::string::size_type equals = setting.assignment.find('=');
    text +=
        setting.assignment.substr(0, equals) + " = " + setting.assignment.substr(equals + 1) + "\n";
  }
  try {
    return ScenarioWithOverrides(scenario_path, ParseToml(text, kSource), kSource);
  } catch (const InputError& error) {
    const std::uint32_t line = error.where().line;
    if (error.where().file != kSource || line == 0 || line > settings.size()) throw;
    const ScenarioSetting& setting = settings[line - 1];
    std::string hint;
    const std::string& assignment = setting.assignment;
    const std::string::size_type equals = assignment.find('=');
    const std::string value = Trimmed(assignment.substr(equals + 1));
    // Quoting is the fix only for a word meant as a string.
    if (error.problem() == InputProblem::kSyntax && LooksLikeBareWord(value)) {
      const std::string quoted = setting.option.rfind("--set ", 0) == 0
                                     ? "--set '" + assignment.substr(0, equals + 1) + "\"" +
                                           value + "\"'"
                                     : setting.option;
      hint = " (VALUE is TOML: quote strings, " + quoted + ")";
    }
    throw FieldError(command + ": " + setting.option + ": " + error.message() + hint,
                     setting.option.substr(0, setting.option.find(' ')), error.allowed());
  }
}

}  // namespace ipmc
