// The pieces the key tables are built from (sim/core/scenario_keys.cc and
// sim/core/strip_keys.cc): a builder for one KeySpec entry, and the TOML
// text a resolved scenario writes for a value.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/choice_table.h"
#include "sim/core/scenario_keys.h"

namespace ipmc {

// Builds one KeySpec entry by named steps.
class Key {
 public:
  Key(std::string name, KeyType type, const char* unit, std::string allowed,
      std::string default_text, std::string meaning) {
    spec_.name = std::move(name);
    spec_.type = type;
    spec_.unit = unit;
    spec_.allowed = std::move(allowed);
    spec_.default_text = std::move(default_text);
    spec_.meaning = std::move(meaning);
  }
  Key& Default(std::string toml) {
    spec_.default_toml = std::move(toml);
    return *this;
  }
  Key& Example(std::string toml) {
    spec_.example_toml = std::move(toml);
    return *this;
  }
  Key& Refused(std::string toml) {
    spec_.refused_toml = std::move(toml);
    return *this;
  }
  Key& Only(const char* selector, const char* value) {
    spec_.only.push_back({selector, value});
    return *this;
  }
  Key& Fields(const char* fields) {
    spec_.fields = fields;
    return *this;
  }
  Key& Reads(KeyReader read) {
    spec_.read = std::move(read);
    return *this;
  }
  Key& Writes(KeyWriter write) {
    spec_.write = std::move(write);
    return *this;
  }
  // A choice whose text the plugin or the controllers parse
  // (ParsePlantAssignment, ...): "uniform|table2".
  Key& Choices(std::string choices) {
    spec_.choices = std::move(choices);
    return *this;
  }
  // A choice parsed by the scenario: its values and allowed text from its
  // table (sim/core/choice_table.h), where adding a value is one line.
  template <typename Enum, std::size_t N>
  Key& Choices(const ChoiceName<Enum> (&table)[N]) {
    spec_.choices = ChoiceTexts(table);
    spec_.allowed = QuotedChoices(KeyChoices(spec_));
    return *this;
  }
  Key& Above(double minimum) { return Lower(Bound::kOpen, minimum); }
  Key& AtLeast(double minimum) { return Lower(Bound::kClosed, minimum); }
  Key& AtMost(double maximum) {
    spec_.upper = Bound::kClosed;
    spec_.maximum = maximum;
    return *this;
  }
  Key& Below(double maximum) {
    spec_.upper = Bound::kOpen;
    spec_.maximum = maximum;
    return *this;
  }
  operator KeySpec() const { return spec_; }

 private:
  Key& Lower(Bound bound, double minimum) {
    spec_.lower = bound;
    spec_.minimum = minimum;
    return *this;
  }
  KeySpec spec_{};
};

// A file key's value (a string) as an absolute path, resolved against the
// scenario file's folder; fails naming the key unless it is a readable
// file (`what` says what to name for an empty one: "a model file (MJCF)").
std::string ReadablePath(const KeyValue& value, const std::string& what);

// Values as a resolved scenario writes them.
inline const std::optional<std::string> kLeftOut = std::nullopt;
std::optional<std::string> TomlString(const std::string& text);
// The shortest text that reads back exactly, always a TOML float ("1000.0",
// "-0.0"), so that even the sign of zero survives.
std::string FloatText(double value);
std::optional<std::string> TomlFloat(double value);
std::optional<std::string> TomlFloats(const std::vector<double>& values);
std::optional<std::string> TomlBool(bool value);
std::optional<std::string> TomlInteger(int value);

// An array of one number per link, config.*kPart.*kGroup.*kField, over a
// scalar key (empty: every link the scalar key's): controller.link_kp
// (config.controller.link_gains.kp), plant.link_a0_mm_per_V
// (config.model.plant.link_a0_mm_per_V), ... (ScenarioConfig,
// sim/core/scenario.h, must be complete where it is used).
template <typename Part, typename Group, Part ScenarioConfig::*kPart, Group Part::*kGroup,
          std::vector<double> Group::*kField>
Key PerLinkKey(const char* name, const char* unit, const char* allowed, const char* meaning,
               const char* example_toml) {
  Key key(name, KeyType::kNumberArray, unit, allowed, "none: every link the scalar key's",
          meaning);
  key.Example(example_toml)
      .Reads([](const KeyValue& v, auto& c) {
        std::vector<double>& values = c.*kPart.*kGroup.*kField;
        values.clear();
        const std::size_t count = v.ArraySize("an array of one number per link");
        if (count == 0) {
          v.Fail(v.name() + ": an empty array; give one value per link, or leave the key out",
                 "an array of one number per link");
        }
        for (std::size_t i = 0; i < count; ++i) values.push_back(v.NumberAt(i));
      })
      .Writes([](const auto& c) -> std::optional<std::string> {
        const std::vector<double>& values = c.*kPart.*kGroup.*kField;
        return values.empty() ? std::nullopt : TomlFloats(values);
      });
  return key;
}

}  // namespace ipmc
