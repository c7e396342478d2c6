// ipmc-swim run: a closed-loop scenario (TOML), or a run's summary.json
// run again, with --set KEY=VALUE and --cycles overrides, its outputs
// (timeseries.csv, states.csv, summary.json) and optionally its film.
//
//   ipmc-swim run SCENARIO [--set KEY=VALUE ...] [--cycles N] [--out DIR]
//       [--format mat,h5] [--video FILE.mp4 ...] [--allow-long]
//
// The run is sim/runs/closed_loop_run.h, its files sim/runs/output.h.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "renders/swim_film.h"

namespace ipmc {

struct RunArgs {
  std::string scenario_path;
  std::vector<std::string> sets;  // --set KEY=VALUE, in order
  int cycles = 0;                 // --cycles, if given
  std::string out_dir;
  std::string video_path;
  FilmConfig film;
  bool allow_long = false;
  std::vector<std::string> formats;  // --format, besides CSV and JSON
  CLI::App* command = nullptr;
};

// Adds subcommand "run" to app, storing options in args.
void AddRunCommand(CLI::App& app, RunArgs& args);

// Runs the scenario, prints its results and writes its files.
int RunScenarioCommand(const RunArgs& args);

}  // namespace ipmc
