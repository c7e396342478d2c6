#include "sim/cli/render_command.h"

#include "sim/cli/command.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <vector>

#include "sim/io/error.h"
#include "sim/io/files.h"
#include "sim/io/numbers.h"
#include "renders/offscreen_renderer.h"
#include "renders/video.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/runs/output.h"
#include "sim/core/scenario.h"

namespace ipmc {
namespace {

constexpr char kRenderCommand[] = "render";
// Trails longer than this would only slow the renderer down.
constexpr int kMaxTrailFrames = 10000;

void Validate(const RenderArgs& args) {
  const auto require = [](bool ok, const char* option, const std::string& allowed,
                          const std::string& got) {
    if (!ok) ThrowOption(kRenderCommand, option, allowed, got);
  };
  require(args.width > 0 && args.width % 2 == 0, "--width", "positive and even",
          std::to_string(args.width));
  require(args.height > 0 && args.height % 2 == 0, "--height", "positive and even",
          std::to_string(args.height));
  require(args.fps > 0.0 && args.fps <= 1000.0, "--fps", "in (0, 1000]", FormatShortest(args.fps));
  require(args.frames_per_cycle >= 1, "--frames-per-cycle", ">= 1",
          std::to_string(args.frames_per_cycle));
  require(args.start_cycle >= 1, "--start-cycle", ">= 1", std::to_string(args.start_cycle));
  require(args.cycles >= 0, "--cycles", ">= 1", std::to_string(args.cycles));
  require(args.trail_frames <= kMaxTrailFrames, "--trail-frames",
          "<= " + std::to_string(kMaxTrailFrames), std::to_string(args.trail_frames));
}

std::string FramePath(const std::string& dir, int index) {
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%05d.png", index);
  return (std::filesystem::path(dir) / name).string();
}

// The PNGs written so far; removed unless the run completes.
class PngSequence {
 public:
  explicit PngSequence(std::string dir) : dir_(std::move(dir)) {}
  ~PngSequence() {
    if (kept_) return;
    for (const std::string& path : written_) std::remove(path.c_str());
  }
  PngSequence(const PngSequence&) = delete;
  PngSequence& operator=(const PngSequence&) = delete;

  void Add(const std::vector<unsigned char>& rgb, int width, int height) {
    if (dir_.empty()) return;
    const std::string path = FramePath(dir_, static_cast<int>(written_.size()));
    WritePng(path, rgb, width, height);
    written_.push_back(path);
  }
  void Keep() { kept_ = true; }

 private:
  std::string dir_;
  std::vector<std::string> written_;
  bool kept_ = false;
};

int RunRender(const RenderArgs& args) {
  Validate(args);
  ScenarioConfig scenario = LoadScenario(args.scenario_path);
  const int first_cycle = args.start_cycle;
  if (args.cycles == 0 && first_cycle > scenario.cycles) {
    throw std::invalid_argument("render: --start-cycle " + std::to_string(first_cycle) +
                                " is after the scenario's last cycle " +
                                std::to_string(scenario.cycles) + " (add --cycles to extend it)");
  }
  const int last_cycle = args.cycles == 0 ? scenario.cycles : first_cycle + args.cycles - 1;
  scenario.cycles = last_cycle;
  scenario.samples_per_cycle = args.frames_per_cycle;
  scenario.output_dir.clear();
  const double period_s = 1.0 / std::abs(scenario.waveform.frequency_Hz);

  EnsureParentDirectory(args.out_path);
  if (!args.png_dir.empty()) EnsureDirectory(args.png_dir);
  Mp4Writer video(args.out_path, args.width, args.height, args.fps);
  PngSequence pngs(args.png_dir);

  RendererOptions options;
  options.trail_length = args.trail_frames < 0 ? args.frames_per_cycle : args.trail_frames;
  std::unique_ptr<OffscreenRenderer> renderer;
  FrameSetup setup;
  setup.overlay.period_s = period_s;
  const auto observer = [&](const mjModel* m, const mjData* d, const ClosedLoopSample& sample) {
    if (!renderer) {
      // The first sample, at t = 0: the model exists from here on, and the
      // centre of mass at rest is the origin of the displacement.
      renderer = std::make_unique<OffscreenRenderer>(m, args.width, args.height, options);
      setup.overlay.origin_m = {sample.pose.com_x_mm * 1e-3, sample.pose.com_y_mm * 1e-3};
    }
    const int cycle = static_cast<int>(std::floor(sample.pose.t_s / period_s + 1e-9)) + 1;
    if (cycle < first_cycle || cycle > last_cycle) return;
    const std::vector<unsigned char> rgb = renderer->Frame(d, setup);
    video.AddFrame(rgb);
    pngs.Add(rgb, args.width, args.height);
  };
  RunScenario(scenario, observer);
  video.Finish();
  pngs.Keep();

  std::printf("%d frames (%dx%d, cycles %d to %d) at %g fps written to %s\n", video.frames(),
              args.width, args.height, first_cycle, last_cycle, args.fps, args.out_path.c_str());
  if (!args.png_dir.empty()) {
    std::printf("frames also written to %s\n", FramePath(args.png_dir, 0).c_str());
  }
  return 0;
}

}  // namespace

void AddRenderCommand(CLI::App& app, RenderArgs& args) {
  CLI::App* cmd = AddCommand(app, kRenderCommand, "Run a scenario and film the swimmer (MP4)");
  cmd->add_option("scenario", args.scenario_path, "Scenario file (TOML)")->required();
  cmd->add_option("--out", args.out_path, "MP4 file to write")->required();
  cmd->add_option("--width", args.width, "Frame width [px], even, at most the model's offwidth");
  cmd->add_option("--height", args.height, "Frame height [px], even, at most the model's offheight");
  cmd->add_option("--fps", args.fps, "Video frame rate [1/s]");
  cmd->add_option("--frames-per-cycle", args.frames_per_cycle, "Frames per wave cycle");
  cmd->add_option("--start-cycle", args.start_cycle, "First cycle filmed (1 = the first)");
  cmd->add_option("--cycles", args.cycles, "Cycles filmed (default: to the scenario's last)")
      ->default_str("");
  cmd->add_option("--trail-frames", args.trail_frames,
                  "Frames of tip trail kept (default: one cycle; 0: none)")
      ->default_str("");
  cmd->add_option("--png-dir", args.png_dir, "Also write every frame as DIR/frame_NNNNN.png");
}

int RunRenderCommand(const CLI::App& app, const RenderArgs& args) {
  if (!app.got_subcommand(kRenderCommand)) return -1;
  return RunRender(args);
}

}  // namespace ipmc
