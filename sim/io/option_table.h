// One table of options per command, read by both front ends: the
// command line (sim/cli/option_flags.h, CLI11) and the Python bindings
// (sim/python/convert.h). Each option is declared once, with its name,
// type, unit, allowed values, meaning and the field of the command's spec
// it sets; its default is the spec's. docs/CONVENTIONS.md gives the
// naming convention and `ipmc-swim options --format markdown` prints
// every table (docs/OPTIONS.md, compared by a test).
//
// Names follow docs/CONVENTIONS.md: snake_case quantity and unit suffix
// with the unit's own capitals ("frequency_Hz", "band_rad_s", "v_max_V"),
// the Python keyword and the JSON field as they are; the command-line flag
// is the same name in lower case with '-' for '_' ("--frequency-hz"). A
// library check names the field (FieldError's field()); the command line
// puts the flag in its place.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace ipmc {

enum class OptionType { kReal, kInteger, kText, kFlag, kRealList, kIntegerList, kPath, kTextList };

// "real", "integer", "text", "flag", "reals", "integers", "path", "texts".
const char* OptionTypeName(OptionType type);

struct OptionInfo {
  OptionInfo() = default;
  OptionInfo(std::string name_, std::string unit_, std::string allowed_, std::string meaning_)
      : name(std::move(name_)),
        unit(std::move(unit_)),
        allowed(std::move(allowed_)),
        meaning(std::move(meaning_)) {}

  std::string name;     // canonical: the Python keyword and JSON field
  std::string unit;     // "Hz", "rad/s", "" for none
  std::string allowed;  // "finite and > 0", "1, 2 or 3"
  std::string meaning;
  std::vector<std::string> choices;  // text options: the words allowed
  // Older spellings still accepted, by both front ends (their flags
  // derived the same way); docs/OPTIONS.md lists them.
  std::vector<std::string> aliases;
  bool required = false;
  bool positional = false;  // command line: an argument, not a flag
  // An option of the command line alone (Python says it its own way, as
  // run's --set, which Python's keyword overrides replace): Python does not
  // read it, docs/OPTIONS.md says so.
  bool command_line_only = false;
  OptionType type = OptionType::kReal;
  std::string default_text;  // the spec's default, as text ("" if none)
};

// The flag of a name: "--" + lower case with '-' for '_'; a one-letter
// name gives "-o".
std::string OptionFlag(const std::string& name);

// `message` with the option name `field` (a whole word) replaced by its
// flag: how the command line relocates a library check's message.
std::string WithFlagFor(const std::string& message, const std::string& field);

// Where an option's value goes in the spec.
template <typename Spec>
using OptionField =
    std::variant<std::function<double&(Spec&)>, std::function<int&(Spec&)>,
                 std::function<unsigned&(Spec&)>, std::function<std::string&(Spec&)>,
                 std::function<bool&(Spec&)>, std::function<std::vector<double>&(Spec&)>,
                 std::function<std::vector<int>&(Spec&)>,
                 std::function<std::vector<std::string>&(Spec&)>>;

template <typename Spec>
struct Option {
  OptionInfo info;
  OptionField<Spec> field;
};

// Text of a default value.
std::string DefaultText(double value);
std::string DefaultText(int value);
std::string DefaultText(unsigned value);
std::string DefaultText(const std::string& value);
std::string DefaultText(bool value);
std::string DefaultText(const std::vector<double>& value);
std::string DefaultText(const std::vector<int>& value);
std::string DefaultText(const std::vector<std::string>& value);

template <typename T>
constexpr OptionType TypeOf() {
  if constexpr (std::is_same_v<T, double>) return OptionType::kReal;
  if constexpr (std::is_same_v<T, int> || std::is_same_v<T, unsigned>) {
    return OptionType::kInteger;
  }
  if constexpr (std::is_same_v<T, std::string>) return OptionType::kText;
  if constexpr (std::is_same_v<T, bool>) return OptionType::kFlag;
  if constexpr (std::is_same_v<T, std::vector<double>>) return OptionType::kRealList;
  if constexpr (std::is_same_v<T, std::vector<std::string>>) return OptionType::kTextList;
  return OptionType::kIntegerList;
}

// A command's options, in the order help and documentation list them.
template <typename Spec>
class OptionTable {
 public:
  OptionTable(std::string command, std::string summary)
      : command_(std::move(command)), summary_(std::move(summary)) {}

  // Adds an option setting field(spec); its default is field(Spec{}).
  template <typename T, typename Get>
  OptionTable& Add(OptionInfo info, Get get) {
    const std::function<T&(Spec&)> field = get;
    RequireNewFlags(info);
    Spec defaults{};
    if (info.type == OptionType::kReal) info.type = TypeOf<T>();
    if (info.default_text.empty() && !info.required) info.default_text = DefaultText(field(defaults));
    options_.push_back({std::move(info), field});
    return *this;
  }
  // A path (a text field whose value is a file or folder).
  template <typename Get>
  OptionTable& AddPath(OptionInfo info, Get get) {
    info.type = OptionType::kPath;
    return Add<std::string>(std::move(info), get);
  }

  const std::string& command() const { return command_; }
  const std::string& summary() const { return summary_; }
  const std::vector<Option<Spec>>& options() const { return options_; }
  std::vector<OptionInfo> Infos() const {
    std::vector<OptionInfo> infos;
    for (const Option<Spec>& option : options_) infos.push_back(option.info);
    return infos;
  }

 private:
  // Two spellings whose flags are one would be one option on the command
  // line and two in Python: a table refuses them.
  void RequireNewFlags(const OptionInfo& info) const {
    std::vector<std::string> names = info.aliases;
    names.push_back(info.name);
    for (const Option<Spec>& option : options_) {
      std::vector<std::string> existing_flags = option.info.aliases;
      existing_flags.push_back(option.info.name);
      for (const std::string& name : names) {
        for (const std::string& other : existing_flags) {
          if (OptionFlag(name) == OptionFlag(other)) {
            throw std::logic_error(command_ + ": options " + other + " and " + name +
                                   " have the same flag " + OptionFlag(name));
          }
        }
      }
    }
  }

  std::string command_, summary_;
  std::vector<Option<Spec>> options_;
};

// Whether the option of field `name` was given (by its flag on the command
// line, its keyword in Python): a library check that depends on it asks.
using OptionGiven = std::function<bool(const std::string& option)>;

// Every command's table without its fields, for the reference.
struct OptionTableInfo {
  std::string command, summary;
  std::vector<OptionInfo> options;
};
template <typename Spec>
OptionTableInfo InfoOf(const OptionTable<Spec>& table) {
  return {table.command(), table.summary(), table.Infos()};
}

// The reference of some tables: "text" (for a terminal) or "markdown"
// (docs/OPTIONS.md).
std::string OptionReference(const std::vector<OptionTableInfo>& tables, const std::string& format);

// A command that prints a reference (`keys`, `options`): its one option.
struct ReferenceCommand {
  std::string format = "text";  // text | markdown
};
// The table of such a command; `markdown_file` is the docs file that
// --format markdown gives.
OptionTable<ReferenceCommand> ReferenceOptions(const std::string& command,
                                               const std::string& summary,
                                               const std::string& markdown_file);
// `options`: every command's options (docs/OPTIONS.md).
const OptionTable<ReferenceCommand>& OptionsOptions();

}  // namespace ipmc
