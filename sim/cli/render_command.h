// The "render" subcommand of ipmc-swim: runs a closed-loop scenario and
// films it from above (renders/offscreen_renderer.h).
//
//   ipmc-swim render SCENARIO --out swim.mp4 [--width 640 --height 480]
//       [--fps 25] [--frames-per-cycle 100] [--start-cycle 1] [--cycles N]
//       [--trail-frames F] [--png-dir DIR]
//
// The scenario runs as `ipmc-swim run` would (same model, controller and
// physics), for cycles 1 .. start-cycle + cycles - 1 (--cycles defaults to
// the scenario's last cycle; more cycles than the scenario names extend the
// run). Its output.samples_per_cycle is replaced by --frames-per-cycle,
// and each recorded sample of the cycles from --start-cycle on becomes a
// frame (the controller's sample count per cycle, divided by a whole
// number, caps the frame count). A frame shows the time, the cycle and the
// net displacement of the centre of mass since t = 0, and trails of the
// tips over the last --trail-frames frames (default: one cycle). The
// scenario's output directory is not written.
//
// --out gets an H.264 MP4 at --fps; --png-dir DIR also gets every frame as
// DIR/frame_00000.png, DIR/frame_00001.png, ... Nothing is written unless
// the whole run succeeded. Bad option values throw std::invalid_argument
// naming the option.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace ipmc {

struct RenderArgs {
  std::string scenario_path;
  std::string out_path;
  int width = 640;
  int height = 480;
  double fps = 25.0;
  int frames_per_cycle = 100;
  int start_cycle = 1;
  int cycles = 0;         // 0: through the scenario's last cycle
  int trail_frames = -1;  // < 0: frames_per_cycle
  std::string png_dir;
};

// Adds subcommand "render" to app, storing its options in args.
void AddRenderCommand(CLI::App& app, RenderArgs& args);

// Runs "render" if app parsed it and returns its exit code; -1 if "render"
// was not the chosen subcommand.
int RunRenderCommand(const CLI::App& app, const RenderArgs& args);

}  // namespace ipmc
