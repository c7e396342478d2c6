// The "render" subcommand of ipmc-swim, and the video options it shares
// with `run --video` (renders/swim_film.h).
//
//   ipmc-swim render RUN_DIR --out swim.mp4 [video options]
//   ipmc-swim render SCENARIO.toml --out swim.mp4 [video options]
//
// RUN_DIR is the output directory of `run` or `gait` (summary.json and
// states.csv): the run is filmed from its recorded states, not simulated
// again. A scenario file is run once, as `ipmc-swim run` would (same
// model, controller and physics), for cycles 1 .. start-cycle + cycles - 1
// (--cycles defaults to the scenario's last cycle; more cycles than the
// scenario names extend the run), recording --frames-per-cycle states per
// cycle, and filmed; its output directory is not written.
//
// Video options: --width-px --height-px --fps --frames-per-cycle --start-cycle
// --cycles --trail-frames --camera fixed|follow --view-mm --center-mm X,Y
// --elevation-deg --azimuth-deg --strip-thickness-mm --no-grid --no-ghost
// --png-dir DIR. --out gets an H.264 MP4 at --fps; --png-dir DIR also gets
// every frame as DIR/frame_00000.png, ... Nothing is written unless the
// whole film succeeded. Bad option values throw FieldError naming the
// option. A progress bar goes to stderr while frames are
// rendered and encoded.
#pragma once

#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "renders/swim_film.h"
#include "sim/runs/closed_loop_run.h"

namespace ipmc {

struct RenderArgs {
  std::string input_path;  // a run's output directory or a scenario file
  std::string out_path;
  FilmConfig film;
};

// Adds the video options to cmd (in an option group named `group`, if not
// empty), storing them in film.
// `cycles_option` names the option of FilmConfig::cycles (`run` has its
// own --cycles, the run's length, and calls it --film-cycles).
void AddVideoOptions(CLI::App* cmd, FilmConfig& film, const std::string& group = "",
                     const std::string& cycles_option = "--cycles");

// Whether any video option was given on cmd's command line (the options
// of `run`, whose cycles option is --film-cycles).
bool AnyVideoOptionGiven(const CLI::App* cmd);

// Runs f(), rethrowing a film's FieldError ("video: FIELD ...",
// FilmConfig::Validate) with the flags in place of the fields' names;
// `cycles_option` is the flag of FilmConfig::cycles.
void TranslatingFilmErrors(const std::string& cycles_option, const std::function<void()>& f);

// Runs the scenario once (SimulateScenario) with a progress bar on the
// terminal and hands the result to `before_filming` (if set); then, with a
// non-empty video_path, films the run from its recorded states into
// video_path (the frame size is checked against the model when the run
// starts) and prints where the video went. Throws as SimulateScenario and
// FilmRun do.
ClosedLoopResult SimulateScenarioWithProgress(
    const ScenarioConfig& scenario, const FilmConfig& film, const std::string& video_path,
    const std::function<void(const ClosedLoopResult&)>& before_filming = {});

// Adds subcommand "render" to app, storing its options in args.
void AddRenderCommand(CLI::App& app, RenderArgs& args);

// Runs "render" if app parsed it and returns its exit code; -1 if "render"
// was not the chosen subcommand.
int RunRenderCommandLine(const CLI::App& app, const RenderArgs& args);

}  // namespace ipmc
