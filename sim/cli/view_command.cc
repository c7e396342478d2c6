#include "sim/cli/view_command.h"

#include <filesystem>
#include <memory>
#include <stdexcept>

#include "sim/cli/command.h"
#include "sim/cli/render_command.h"
#include "sim/core/scenario.h"

namespace ipmc {
namespace {

constexpr char kViewCommand[] = "view";
// A panel's default size [px]: two side by side fit a 1920 px screen.
constexpr int kPanelWidth_px = 960;
constexpr int kPanelHeight_px = 600;

ViewedRun OpenInput(const std::string& input, const FilmConfig& film) {
  ViewedRun run;
  if (std::filesystem::is_directory(input)) {
    run.recording = std::make_unique<RunRecording>(LoadRunRecording(input));
    return run;
  }
  // A scenario, run live for the cycles the film shows (as `render` runs it).
  ScenarioConfig scenario = LoadScenario(input);
  if (film.cycles == 0 && film.start_cycle > scenario.run.cycles) {
    throw std::invalid_argument("view: --start-cycle " + std::to_string(film.start_cycle) +
                                " is after the scenario's last cycle " +
                                std::to_string(scenario.run.cycles) +
                                " (add --cycles to extend it)");
  }
  if (film.cycles > 0) scenario.run.cycles = film.start_cycle + film.cycles - 1;
  run.live = std::make_unique<LiveRun>(scenario);
  return run;
}

int RunView(const ViewArgs& args) {
  args.viewer.Validate();
  std::vector<ViewedRun> runs;
  for (const std::string& input : args.inputs) {
    runs.push_back(OpenInput(input, args.viewer.film));
    if (args.inputs.size() > 1) {
      runs.back().title = std::filesystem::path(input).lexically_normal().filename().string();
      if (runs.back().title.empty()) {
        runs.back().title = std::filesystem::path(input).lexically_normal().parent_path().filename().string();
      }
    }
  }
  return RunViewer(runs, args.viewer);
}

}  // namespace

void AddViewCommand(CLI::App& app, ViewArgs& args) {
  CLI::App* cmd = AddCommand(
      app, kViewCommand,
      "Watch runs in a window: recorded runs or a scenario live, side by side, time-synchronised");
  cmd->add_option("inputs", args.inputs,
                  "Runs' output directories (states.csv, summary.json) or scenario files (TOML, "
                  "run live); one panel each")
      ->required();
  args.viewer.film.width = kPanelWidth_px;
  args.viewer.film.height = kPanelHeight_px;
  AddVideoOptions(cmd, args.viewer.film);
  cmd->remove_option(cmd->get_option("--png-dir"));
  cmd->add_option("--speed", args.viewer.speed,
                  "Run seconds per second (default: the film's, fps x period / frames-per-cycle)");
  cmd->add_flag("--paused", args.viewer.paused, "Start paused");
  cmd->add_option("--script", args.viewer.script,
                  "Actions, one per drawn frame: key names (below), NAME*N, shot:FILE.png, wait:N, "
                  "scroll:N, drag:DX:DY; e.g. 'h,right*10,shot:a.png,q'");
  cmd->footer(ViewerKeysText());
}

int RunViewCommandLine(const CLI::App& app, const ViewArgs& args) {
  if (!app.got_subcommand(kViewCommand)) return -1;
  int status = 0;
  TranslatingFilmErrors("--cycles", [&] { status = RunView(args); });
  return status;
}

}  // namespace ipmc
