#include "sim/cli/plot_command.h"

#include <cstdio>
#include <string>
#include <vector>

#include "sim/cli/command.h"

namespace ipmc {
namespace {

constexpr char kPlotCommand[] = "plot";

// The kind-specific options given on the command line, by their names
// without "--".
std::vector<std::string> GivenKindOptions(const CLI::App& command) {
  std::vector<std::string> given;
  for (const std::string& option : FigureKindOptionNames()) {
    if (command.count("--" + option) > 0) given.push_back(option);
  }
  return given;
}

int RunPlot(const CLI::App& command, const PlotArgs& args) {
  const FigureKind kind = FigureKindOf(args.kind);
  CheckFigureOptionsApply(kind, GivenKindOptions(command));
  const FigureReport report = DrawFigureOf(kind, args.input_paths, args.figure, args.out_path);
  std::string inputs;
  for (const std::string& input : args.input_paths) inputs += (inputs.empty() ? "" : ", ") + input;
  std::printf("plot %s of %s written to %s\n  %s\n", args.kind.c_str(), inputs.c_str(),
              args.out_path.c_str(), report.title.c_str());
  for (const std::string& note : report.notes) std::printf("  %s\n", note.c_str());
  return 0;
}

}  // namespace

void AddPlotCommand(CLI::App& app, PlotArgs& args) {
  FigureOptions& f = args.figure;
  CLI::App* cmd = AddCommand(
      app, kPlotCommand, "Draw a figure with gnuplot (PDF, SVG or PNG by the extension of --out)");
  cmd->add_option("kind", args.kind,
                  "bode (Fig. 9/10) | step (Fig. 11) | tracking (Fig. 12a) | waveform (Fig. 12b) "
                  "| surface (Fig. 13) | trajectory | identification (Fig. 7) | sweep | compare | regime")
      ->required()
      ->check(CLI::IsMember(FigureKindNames()));
  cmd->add_option("input", args.input_paths,
                  "bode.csv, step.csv, timeseries.csv (tracking, waveform, surface, trajectory), "
                  "response.csv (identification), a sweep table, (compare) two or more run "
                  "directories, or (regime) a run's summary.json")
      ->required();
  cmd->add_option("-o,--out", args.out_path, "Figure to write: FILE.pdf, FILE.svg or FILE.png")
      ->required();
  cmd->add_option("--title", f.title, "Figure title (default: what is shown)");
  cmd->add_option("--width-px", f.size.width_px,
                  "Image width [px] at 150 px/in (default: the kind's)")
      ->default_str("");
  cmd->add_option("--height-px", f.size.height_px,
                  "Image height [px] at 150 px/in (default: the kind's)")
      ->default_str("");
  cmd->add_option("--curves", f.curves,
                  "bode: curves to draw, of plant, controller, open_loop, reference_open_loop")
      ->delimiter(',');
  cmd->add_option("--instants", f.instants,
                  "waveform: number of instants over the last wave period");
  cmd->add_option("--times-s", f.times_s, "waveform: instants [s] (nearest samples)")
      ->delimiter(',')
      ->default_str("");
  cmd->add_option("--period-s", f.period_s,
                  "waveform, trajectory: wave period [s] (default: period_s of summary.json "
                  "beside INPUT)")
      ->default_str("");
  cmd->add_option("--max-lines", f.max_lines, "surface: most time rows in the x-t map");
  cmd->add_option("--x", f.x_column,
                  "sweep: column on the x axis (NAME[i]: element i of an array column)");
  cmd->add_option("--y", f.y_column, "sweep: column on the y axis");
  cmd->add_option("--group", f.group_column, "sweep: one curve per value of this column");
  cmd->add_flag("--log-x", f.log_x, "sweep: logarithmic x axis");
  cmd->add_flag("--log-y", f.log_y, "sweep: logarithmic y axis");
  cmd->add_option("--labels", f.labels,
                  "compare: the legend's name of each run, one per run directory, in their order "
                  "(default: what differs between their resolved scenarios)");
}

int RunPlotCommandLine(const CLI::App& app, const PlotArgs& args) {
  if (!app.got_subcommand(kPlotCommand)) return -1;
  return RunPlot(*app.get_subcommand(kPlotCommand), args);
}

}  // namespace ipmc
