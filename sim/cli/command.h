// What every command of ipmc-swim shares when it registers itself.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace ipmc {

// Adds subcommand `name` to `app`; every option added to it shows its
// default in --help (options whose default is a placeholder, such as 0
// for "the kind's own", clear it with ->default_str("")).
inline CLI::App* AddCommand(CLI::App& app, const std::string& name,
                            const std::string& description) {
  CLI::App* command = app.add_subcommand(name, description);
  command->option_defaults()->always_capture_default();
  return command;
}

}  // namespace ipmc
