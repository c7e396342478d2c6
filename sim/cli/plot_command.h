// The "plot" subcommand of ipmc-swim: the figures of renders/figures.h
// (which says what each kind draws and from which columns), drawn with
// gnuplot into PDF, SVG or PNG by the extension of --out.
//
//   ipmc-swim plot KIND INPUT --out FILE.{pdf,svg,png} [--title TEXT]
//                  [--width-px W] [--height-px H] [kind's options]
//   ipmc-swim plot compare RUN_DIR RUN_DIR... --out FILE
//
// KIND: bode | step | tracking | waveform | surface | trajectory |
// identification | sweep | compare. An option that does not apply to KIND is
// refused. Errors throw FieldError (bad options, an unknown output
// format), InputError (missing or non-numeric columns; the message names
// INPUT and the column) or std::runtime_error (gnuplot missing or failing,
// I/O); no FILE is left behind then.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "renders/figures.h"

namespace ipmc {

struct PlotArgs {
  std::string kind;
  std::vector<std::string> input_paths;  // one; compare: run directories
  std::string out_path;
  FigureOptions figure;
};

// Adds subcommand "plot" to app, storing options in args.
void AddPlotCommand(CLI::App& app, PlotArgs& args);

// Runs "plot" if app parsed it and returns 0; returns -1 if it was not
// chosen. Throws as described above.
int RunPlotCommandLine(const CLI::App& app, const PlotArgs& args);

}  // namespace ipmc
