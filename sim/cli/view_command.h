// The "view" subcommand of ipmc-swim: an interactive window on runs
// (renders/viewer.h).
//
//   ipmc-swim view RUN_DIR|SCENARIO.toml... [video options] [--speed X]
//                  [--paused] [--script ACTIONS]
//
// Each input is a panel, side by side, all at one simulated time: a run's
// output directory (states.csv, summary.json) read back, or a scenario
// file run live in a thread while the window shows its states. The video
// options of `render` (render_command.h) set each panel's image and what
// it shows, so a panel shows what the film shows; --width-px/--height-px
// are a panel's size. The keys are listed by `view --help` and in the
// window. Without a display it says so in one line and exits 1.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "renders/viewer.h"

namespace ipmc {

struct ViewArgs {
  std::vector<std::string> inputs;
  ViewerConfig viewer;
};

// Adds subcommand "view" to app, storing its options in args.
void AddViewCommand(CLI::App& app, ViewArgs& args);

// Runs "view" if app parsed it and returns its exit code; -1 if "view"
// was not the chosen subcommand.
int RunViewCommandLine(const CLI::App& app, const ViewArgs& args);

}  // namespace ipmc
