// A command's option table (sim/io/option_table.h) as CLI11 options: each
// option becomes its flag (and its aliases' flags, or an argument if
// positional), bound to its field of `spec`, with its meaning, unit,
// allowed words and default in --help. The library's checks name fields;
// TranslatingFieldErrors puts the flag in the field's place.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <CLI/CLI.hpp>

#include "sim/cli/command.h"
#include "sim/base/error.h"
#include "sim/io/option_table.h"

namespace ipmc {

inline std::string OptionHelp(const OptionInfo& info) {
  std::string help = info.meaning;
  if (!info.unit.empty()) help += " [" + info.unit + "]";
  if (!info.allowed.empty()) help += "; " + info.allowed;
  return help;
}

// The CLI11 name of an option: "--name,--alias" (or the argument's name).
inline std::string CliNames(const OptionInfo& info) {
  if (info.positional) return info.name;
  std::string names = OptionFlag(info.name);
  for (const std::string& alias : info.aliases) names += "," + OptionFlag(alias);
  return names;
}

template <typename Spec>
void AddTableOptions(CLI::App* command, const OptionTable<Spec>& table, Spec& spec) {
  for (const Option<Spec>& option : table.options()) {
    const OptionInfo& info = option.info;
    std::visit(
        [&](const auto& field) {
          auto& value = field(spec);
          using T = std::decay_t<decltype(value)>;
          CLI::Option* added = nullptr;
          if constexpr (std::is_same_v<T, bool>) {
            added = command->add_flag(CliNames(info), value, OptionHelp(info));
          } else {
            added = command->add_option(CliNames(info), value, OptionHelp(info));
            if constexpr (std::is_same_v<T, std::vector<double>> ||
                          std::is_same_v<T, std::vector<int>>) {
              added->delimiter(',');
            }
            if constexpr (std::is_same_v<T, std::vector<std::string>>) {
              // One word per occurrence, repeatable (a value may hold commas).
              added->expected(1)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
            }
          }
          if (!info.choices.empty()) added->check(CLI::IsMember(info.choices));
          if (info.type == OptionType::kPath) {
            // --out '' names nothing (Python's out='' is refused alike).
            added->check(CLI::Validator(
                [](std::string& text) {
                  return text.empty() ? std::string("an empty path names no file or folder")
                                      : std::string();
                },
                ""));
          }
          if (info.required) added->required();
          if (info.default_text.empty()) added->default_str("");
        },
        option.field);
  }
}

// Whether the option named `name` was given on the command line.
inline bool GivenOnCommandLine(const CLI::App& command, const std::string& name) {
  return command.count(OptionFlag(name)) > 0;
}

// Runs f(), rethrowing a FieldError about one of the table's options with
// the flags in place of the names of the table's options it mentions.
template <typename Spec, typename F>
auto TranslatingFieldErrors(const OptionTable<Spec>& table, F&& f) {
  try {
    return f();
  } catch (const FieldError& error) {
    bool ours = false;
    for (const Option<Spec>& option : table.options()) {
      ours = ours || (option.info.name == error.field() && !option.info.positional);
    }
    if (!ours) throw;
    // The command's own name, which leads the message, is not an option.
    const std::string lead = table.command() + ": ";
    std::string message = error.what();
    const std::size_t from = message.rfind(lead, 0) == 0 ? lead.size() : 0;
    std::string text = message.substr(from);
    for (const Option<Spec>& option : table.options()) {
      if (!option.info.positional) text = WithFlagFor(text, option.info.name);
    }
    message = message.substr(0, from) + text;
    throw FieldError(message, OptionFlag(error.field()), error.allowed());
  }
}

// A command whose options are one table: the spec they fill and the
// subcommand, once added.
template <typename Spec>
struct TableCommand {
  Spec spec;
  CLI::App* command = nullptr;

  // Whether the command line chose this command.
  bool Chosen() const { return command != nullptr && command->parsed(); }
  // Whether the option of field `name` was given (the library's OptionGiven).
  std::function<bool(const std::string&)> Given() const {
    const CLI::App* app = command;
    return [app](const std::string& name) { return GivenOnCommandLine(*app, name); };
  }
};

// Adds the table's command, with its options bound to args.spec.
template <typename Spec>
CLI::App* AddTableCommand(CLI::App& app, const OptionTable<Spec>& table,
                          TableCommand<Spec>& args) {
  args.command = AddCommand(app, table.command(), table.summary());
  AddTableOptions(args.command, table, args.spec);
  return args.command;
}

}  // namespace ipmc
