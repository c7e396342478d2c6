// What every command of ipmc-swim shares when it registers itself.
#pragma once

#include <functional>
#include <memory>
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

// What runs a registered command once the command line is parsed: its
// exit status, or -1 when the command line chose another command.
using CommandRunner = std::function<int()>;

// The one signature of sim/cli/main.cc's command table: adds a command's
// subcommand (or subcommands) to the program and returns its runner.
using CommandRegistration = std::function<CommandRunner(CLI::App& app)>;

// A command's registration from its file pair's Add and Run functions; its
// arguments live as long as the runner.
template <typename Args>
CommandRegistration Registration(void (*add)(CLI::App&, Args&), int (*run)(const Args&)) {
  return [add, run](CLI::App& app) -> CommandRunner {
    auto args = std::make_shared<Args>();
    add(app, *args);
    return [run, args] { return run(*args); };
  };
}

// The same for a Run function that also reads the parsed program.
template <typename Args>
CommandRegistration Registration(void (*add)(CLI::App&, Args&),
                                 int (*run)(const CLI::App&, const Args&)) {
  return [add, run](CLI::App& app) -> CommandRunner {
    auto args = std::make_shared<Args>();
    add(app, *args);
    return [run, args, &app] { return run(app, *args); };
  };
}

}  // namespace ipmc
