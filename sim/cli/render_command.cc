#include "sim/cli/render_command.h"

#include "sim/cli/command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <vector>

#include "sim/core/scenario.h"
#include "sim/core/simulation.h"
#include "sim/cli/interrupt.h"
#include "sim/cli/run_watch.h"
#include "sim/io/files.h"
#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/io/option_table.h"
#include "sim/io/progress_bar.h"

namespace ipmc {
namespace {

constexpr char kRenderCommand[] = "render";
// Every video option, for AnyVideoOptionGiven.
constexpr const char* kVideoOptions[] = {
    "--width-px",     "--height-px",        "--fps",           "--frames-per-cycle",
    "--start-cycle", "--film-cycles", "--trail-frames",  "--camera",
    "--view-mm",   "--center-mm",     "--elevation-deg", "--azimuth-deg",
    "--strip-thickness-mm", "--no-grid", "--no-ghost",   "--png-dir"};

// A progress bar on stderr for a film, which a SIGINT or SIGTERM stops
// at the next frame (the unfinished video is removed).
class FilmProgressBar {
 public:
  explicit FilmProgressBar(const InterruptAtBoundary& interrupt)
      : bar_("rendering", "frames", StderrIsTerminal(), /*quarter_lines=*/true),
        interrupt_(interrupt) {}
  FilmProgress Callback() {
    return [this](int done, int total) {
      if (!started_) {
        bar_.Start(total);
        started_ = true;
      }
      bar_.Update(done);
      if (!interrupt_.Requested()) return;
      interrupt_.ThrowIfRequested(FormatText("stopped at frame %d of %d; %s", done, total,
                                             kept_.c_str()));
    };
  }
  void Finish() { bar_.Finish(); }
  // What a stop keeps, for its message.
  void SetKept(std::string kept) { kept_ = std::move(kept); }

 private:
  ProgressBar bar_;
  const InterruptAtBoundary& interrupt_;
  bool started_ = false;
  std::string kept_ = "the video was not written";
};

// The simulated time a closed-loop scenario reaches [s].
double ScenarioDuration_s(const ScenarioConfig& scenario) {
  return scenario.run.cycles / std::abs(scenario.waveform.frequency_Hz);
}

void PrintFilmSummary(const FilmSummary& summary, const FilmConfig& film,
                      const std::string& out_path) {
  std::printf("%d frames (%dx%d, cycles %d to %d, %.3g x real time, %.4g px/mm) at %g fps "
              "written to %s\n",
              summary.frames, film.width, film.height, summary.first_cycle, summary.last_cycle,
              summary.speedup, summary.pixels_per_mm, film.fps, out_path.c_str());
  if (!film.png_dir.empty()) {
    std::printf("frames also written to %s\n",
                (std::filesystem::path(film.png_dir) / "frame_00000.png").c_str());
  }
}

int RunRender(const RenderArgs& args) {
  args.film.Validate();
  const std::filesystem::path input(args.input_path);
  RefuseOverwritingInputs(kRenderCommand, "--out", args.out_path,
                          {args.input_path, (input / "states.csv").string(),
                           (input / "summary.json").string()});
  RequireWritableParent(args.out_path);
  if (std::filesystem::is_directory(args.input_path)) {
    const RunRecording recording = LoadRunRecording(args.input_path);
    const InterruptAtBoundary interrupt("interrupted: stopping at the next frame (again: at once)");
    FilmProgressBar bar(interrupt);
    const FilmSummary summary = FilmRun(recording.View(), args.film, args.out_path, bar.Callback());
    bar.Finish();
    PrintFilmSummary(summary, args.film, args.out_path);
    return 0;
  }
  ScenarioConfig scenario = LoadScenario(args.input_path);
  const int first_cycle = args.film.start_cycle;
  if (args.film.cycles == 0 && first_cycle > scenario.run.cycles) {
    throw std::invalid_argument("render: --start-cycle " + std::to_string(first_cycle) +
                                " is after the scenario's last cycle " +
                                std::to_string(scenario.run.cycles) +
                                " (add --cycles to extend it)");
  }
  scenario.run.cycles =
      args.film.cycles == 0 ? scenario.run.cycles : first_cycle + args.film.cycles - 1;
  scenario.output.samples_per_cycle = args.film.frames_per_cycle;
  scenario.output.dir.clear();
  SimulateScenarioWithProgress(scenario, args.film, args.out_path);
  return 0;
}

}  // namespace

void AddVideoOptions(CLI::App* cmd, FilmConfig& film, const std::string& group,
                     const std::string& cycles_option) {
  CLI::App* g = group.empty() ? cmd : cmd->add_option_group(group);
  g->add_option("--width-px", film.width, "Frame width [px], even, at most the model's offwidth")
      ->capture_default_str();
  g->add_option("--height-px", film.height, "Frame height [px], even, at most the model's offheight")
      ->capture_default_str();
  g->add_option("--fps", film.fps, "Video frame rate [1/s]")->capture_default_str();
  g->add_option("--frames-per-cycle", film.frames_per_cycle, "Frames per wave cycle")
      ->capture_default_str();
  g->add_option("--start-cycle", film.start_cycle, "First cycle filmed (1 = the first)")
      ->capture_default_str();
  g->add_option(cycles_option, film.cycles, "Cycles filmed (default: to the run's last)");
  g->add_option("--trail-frames", film.trail_frames,
                "Frames of tip trail kept (default: one cycle; 0: none)");
  g->add_option_function<std::string>(
       "--camera",
       [&film](const std::string& camera) {
         film.camera = camera == "follow" ? FilmCamera::kFollow : FilmCamera::kFixed;
       },
       "fixed: still, framing the whole swim over a mm grid; follow: on the centre of mass")
      ->check(CLI::IsMember({"fixed", "follow"}))
      ->default_str("fixed");
  g->add_option("--view-mm", film.view_mm,
                "Image width at the body's plane [mm] (default: fit the swim, or 1/0.6 body "
                "lengths when following)");
  g->add_option("--center-mm", film.center_mm, "Fixed camera: image centre X,Y [mm]")
      ->delimiter(',')->expected(2);
  g->add_option("--elevation-deg", film.elevation_deg,
                "Camera elevation [deg], -90 (top-down) to -5 (grazing)")
      ->capture_default_str();
  g->add_option("--azimuth-deg", film.azimuth_deg, "Camera azimuth [deg] (90: +x to the right)")
      ->capture_default_str();
  g->add_option_function<double>(
      "--strip-thickness-mm", [&film](double mm) { film.strip_thickness_mm = mm; },
      "Drawn strip thickness [mm] (physics unchanged; default 2 % of the body length; 0: "
      "true 250 um)");
  g->add_flag_function("--no-grid", [&film](std::int64_t) { film.grid = false; },
                       "Plain background: no millimetre grid and scale bar");
  g->add_flag_function("--no-ghost", [&film](std::int64_t) { film.ghost = false; },
                       "No ghost of the ideal travelling wave");
  g->add_option("--png-dir", film.png_dir, "Also write every frame as DIR/frame_NNNNN.png");
}

void TranslatingFilmErrors(const std::string& cycles_option, const std::function<void()>& f) {
  try {
    f();
  } catch (const FieldError& error) {
    const std::string lead = "video: ";
    std::string message = error.what();
    if (message.rfind(lead, 0) != 0) throw;
    std::string field = error.field();
    for (const char* option : kVideoOptions) {
      std::string name = std::string(option).substr(2);
      std::replace(name.begin(), name.end(), '-', '_');
      if (name == "film_cycles") name = "cycles";
      const std::string flag = name == "cycles" ? cycles_option : OptionFlag(name);
      // WithFlagFor gives OptionFlag(name); run's cycles is --film-cycles.
      std::string text = WithFlagFor(message.substr(lead.size()), name);
      if (flag != OptionFlag(name)) {
        for (std::size_t at = text.find(OptionFlag(name)); at != std::string::npos;
             at = text.find(OptionFlag(name), at + flag.size())) {
          text.replace(at, OptionFlag(name).size(), flag);
        }
      }
      message = lead + text;
      if (field == name) field = flag;
    }
    throw FieldError(message, field, error.allowed());
  }
}

bool AnyVideoOptionGiven(const CLI::App* cmd) {
  for (const char* option : kVideoOptions) {
    if (cmd->count(option) > 0) return true;
  }
  return false;
}

ClosedLoopResult SimulateScenarioWithProgress(
    const ScenarioConfig& scenario, const FilmConfig& film, const std::string& video_path,
    const std::function<void(const ClosedLoopResult&)>& before_filming) {
  RunWatch watch("running", ScenarioDuration_s(scenario));
  const SampleObserver observer = [&](const mjModel*, const mjData* d, const ClosedLoopSample&) {
    watch.At(d->time);
  };
  const RunHeartbeat heartbeat = [&](double t_s) { watch.At(t_s); };
  const auto report = [&](const ClosedLoopResult& result) {
    watch.Finish();
    if (before_filming) before_filming(result);
  };
  if (video_path.empty()) {
    const ClosedLoopResult result = SimulateScenario(scenario, observer, heartbeat);
    report(result);
    return result;
  }
  FilmProgressBar bar(watch.interrupt());
  bar.SetKept("the video was not written; the run's results above are kept");
  FilmSummary summary;
  const ClosedLoopResult result = SimulateAndFilmScenario(scenario, film, video_path, report,
                                                          bar.Callback(), &summary, observer,
                                                          heartbeat);
  bar.Finish();
  PrintFilmSummary(summary, film, video_path);
  return result;
}

void AddRenderCommand(CLI::App& app, RenderArgs& args) {
  CLI::App* cmd = AddCommand(
      app, kRenderCommand, "Film a run from its output directory, or run a scenario and film it (MP4)");
  cmd->add_option("input", args.input_path,
                  "A run's output directory (states.csv, summary.json) or a scenario file (TOML)")
      ->required();
  cmd->add_option("-o,--out", args.out_path, "MP4 file to write")->required();
  AddVideoOptions(cmd, args.film);
}

int RunRenderCommandLine(const CLI::App& app, const RenderArgs& args) {
  if (!app.got_subcommand(kRenderCommand)) return -1;
  TranslatingFilmErrors("--cycles", [&] { RunRender(args); });
  return 0;
}

}  // namespace ipmc
