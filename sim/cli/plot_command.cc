#include "sim/cli/plot_command.h"

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/cli/command.h"
#include "plugin/base/error.h"
#include "sim/io/files.h"

namespace ipmc {
namespace {

constexpr char kPlotCommand[] = "plot";

constexpr int kMinImagePx = 200;
constexpr int kMaxImagePx = 10000;

// Refuses options that KIND does not use, so that none is silently
// ignored, and image sizes out of range.
void ValidateOptions(const CLI::App& command, const PlotArgs& args) {
  const std::pair<const char*, std::vector<const char*>> option_kinds[] = {
      {"--curves", {"bode"}},       {"--instants", {"waveform"}},
      {"--times-s", {"waveform"}},  {"--period-s", {"waveform", "trajectory"}},
      {"--max-lines", {"surface"}}, {"--x", {"sweep"}},
      {"--y", {"sweep"}},           {"--group", {"sweep"}},
      {"--log-x", {"sweep"}},       {"--log-y", {"sweep"}}};
  for (const auto& [option, kinds] : option_kinds) {
    if (command.count(option) == 0) continue;
    bool applies = false;
    std::string names;
    for (const char* kind : kinds) {
      applies = applies || args.kind == kind;
      names += (names.empty() ? "" : ", ") + std::string(kind);
    }
    if (!applies) {
      throw FieldError(std::string(kPlotCommand) + ": " + option + " applies to plot " + names +
                           " only, not " + args.kind,
                       option, "plot " + names);
    }
  }
  const std::pair<const char*, int> sizes[] = {{"--width-px", args.figure.size.width_px},
                                               {"--height-px", args.figure.size.height_px}};
  for (const auto& [option, size] : sizes) {
    if (command.count(option) > 0 && (size < kMinImagePx || size > kMaxImagePx)) {
      const std::string range =
          "[" + std::to_string(kMinImagePx) + ", " + std::to_string(kMaxImagePx) + "]";
      throw FieldError(std::string(kPlotCommand) + ": " + option + " must be in " + range +
                           ", got " + std::to_string(size),
                       option, range);
    }
  }
}

int RunPlot(const CLI::App& command, const PlotArgs& args) {
  // The input, or a file of the input folder (a run's outputs).
  const std::filesystem::path out(args.out_path);
  RefuseOverwritingInputs(
      "plot", "--out", args.out_path,
      {args.input_path, (std::filesystem::path(args.input_path) / out.filename()).string()});
  ValidateOptions(command, args);
  RequireWritableParent(args.out_path);
  const FigureReport report =
      DrawFigureOf(FigureKindOf(args.kind), args.input_path, args.figure, args.out_path);
  std::printf("plot %s of %s written to %s\n  %s\n", args.kind.c_str(), args.input_path.c_str(),
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
                  "| surface (Fig. 13) | trajectory | identification (Fig. 7) | sweep")
      ->required()
      ->check(CLI::IsMember(FigureKindNames()));
  cmd->add_option("input", args.input_path,
                  "bode.csv, step.csv, timeseries.csv (tracking, waveform, surface, trajectory), "
                  "response.csv (identification) or a sweep table")
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
}

int RunPlotCommand(const CLI::App& app, const PlotArgs& args) {
  if (!app.got_subcommand(kPlotCommand)) return -1;
  return RunPlot(*app.get_subcommand(kPlotCommand), args);
}

}  // namespace ipmc
