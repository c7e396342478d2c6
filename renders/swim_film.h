// Filming a run from its recorded states (sim/runs/recorded_states.h): the
// run is simulated once, and its video is made afterwards, right after it
// (`run SCENARIO --video`) or later from its output directory (`render`).
//
// Frames. `frames_per_cycle` frames per wave period T, from the start of
// cycle `start_cycle` for `cycles` cycles: frame k shows the state at
//   t_k = (start_cycle - 1) T + k T / frames_per_cycle,
// taken from the recorded states (exact where t_k is a recorded sample, as
// when frames_per_cycle divides the run's samples per cycle; interpolated
// between samples otherwise). At `fps` frames per second the video plays
// fps T / frames_per_cycle times faster than the run (the overlay says so).
//
// Camera (renders/offscreen_renderer.h):
//   fixed (default)  stays put for the whole video, so the swimming shows
//                    against the millimetre grid. It frames the body over
//                    every filmed frame (and the ghost) with a margin, below
//                    the overlay's band, unless view_mm / center_mm say
//                    otherwise.
//   follow           looks at the centre of mass; the body's rest length
//                    fills 60 % of the width unless view_mm says otherwise.
// The overlay shows time, cycle, playback speed, the caller's rows
// (controller, actuation, ...) and the net displacement of the centre of
// mass since the run's first recorded state.
//
// Ghost: the caller's ideal shape y(x, t) [m] in the head's frame (x along
// the root body's x axis from hinge j1, y along its y axis), drawn faintly
// under the body; for a closed-loop run, the scenario's travelling wave
// faded in like its references (ScenarioIdealShape).
//
// Output: an H.264 MP4 written to a temporary name and renamed when
// complete (renders/video.h); with png_dir, also every frame as
// DIR/frame_00000.png, ... (removed again if the film fails).
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "renders/offscreen_renderer.h"
#include "sim/core/scenario.h"
#include "sim/core/simulation.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/runs/recorded_states.h"

namespace ipmc {

enum class FilmCamera { kFixed, kFollow };

struct FilmConfig {
  int width = 1280;                // even, at most the model's offwidth
  int height = 720;                // even, at most the model's offheight
  double fps = 25.0;               // (0, 1000]
  int frames_per_cycle = 100;      // >= 1
  int start_cycle = 1;             // >= 1
  int cycles = 0;                  // >= 0; 0: through the run's last cycle
  int trail_frames = -1;           // [0, 10000], 0: none; -1: one cycle
  FilmCamera camera = FilmCamera::kFixed;
  double view_mm = 0.0;            // [0, 10000]; 0: fit the body (fixed) or 1 / 0.6 of its length (follow)
  std::vector<double> center_mm;   // empty or (x, y), fixed camera only
  double elevation_deg = -90.0;    // [-90, -5]; -90: top-down
  double azimuth_deg = 90.0;       // [-360, 360]; 90: +x right
  std::optional<double> strip_thickness_mm;  // [0, 10]; unset: 2 % of the body length
  bool grid = true;
  bool ghost = true;
  std::string png_dir;             // non-empty: also write PNG frames there

  // Throws FieldError "video: FIELD must be RANGE (got V)" naming the
  // option by its name (width_px, frames_per_cycle, center_mm, ...: the
  // flag's name with '_' for '-'); the command line puts its flag in place.
  void Validate() const;
};

// What is filmed.
struct FilmedRun {
  const mjModel* model = nullptr;
  const RecordedStates* states = nullptr;
  double period_s = 0.0;  // > 0, the wave (or gait) period
  int cycles = 0;         // the run's cycles
  std::vector<std::array<std::string, 2>> overlay_rows;  // label, value
  // y [m] of the ideal shape at x [m] from hinge j1 and time t [s]; empty:
  // no ghost.
  std::function<double(double x_m, double t_s)> ideal_y_m;
};

struct FilmSummary {
  int frames = 0;
  int first_cycle = 0, last_cycle = 0;
  double pixels_per_mm = 0.0;  // at the camera's look-at point
  double view_width_mm = 0.0;
  double speedup = 0.0;        // run seconds per video second
};

// Called after each frame with (frames done, frames in all).
using FilmProgress = std::function<void(int done, int total)>;

// A closed-loop run of `scenario` on model m (the run's own model, e.g.
// copied when the run starts): its states, period, cycles, overlay rows
// and ghost. Points into result.states: keep result alive while filming.
FilmedRun ClosedLoopFilm(const mjModel* m, const ClosedLoopResult& result,
                         const ScenarioConfig& scenario);

// A run read back from its output directory (timeseries.csv,
// states.csv, summary.json of `run` or `gait`): a closed-loop run's
// scenario file (summary.json inputs.scenario) gives the model, the ghost
// and the overlay rows; a gait run's model file (inputs.model) gives the
// model.
struct RunRecording {
  ModelPtr model;
  RecordedStates states;
  double period_s = 0.0;
  int cycles = 0;
  std::vector<std::array<std::string, 2>> overlay_rows;
  std::function<double(double x_m, double t_s)> ideal_y_m;
  FilmedRun View() const;  // points into this recording
};

// Throws InputError (a std::runtime_error) naming the directory and the
// missing file, or summary.json and the missing field, or the field
// inputs.model_sha256 when the model has changed since the run
// (ScenarioOfSummary, ModelOfGaitSummary: sim/runs/output.h).
RunRecording LoadRunRecording(const std::string& dir);

// The overlay's playback row: "25 x real time".
std::string PlaybackSpeedText(double factor);

// The renderer's options for a film: its trails and strip thickness.
RendererOptions FilmRendererOptions(const FilmConfig& config);

// How a film draws its frames, for FilmRun and for a window that shows
// the same frames (renders/viewer.h): frame k at time_s(k), d's state at
// a time from the recorded states, and the frame's camera, overlay and
// ghost. The camera is set up for `renderer`'s image (its size, strip
// thickness and overlay lines). Throws FieldError as FilmRun does for bad
// options, cycles the run does not have, or a run without states or
// period. Points into `run`'s states: keep them alive (they may grow, as
// a live run's do; the camera frames the states there are when made).
class FilmFrames {
 public:
  FilmFrames(const FilmedRun& run, const FilmConfig& config, OffscreenRenderer& renderer);
  FilmFrames(const FilmFrames&) = delete;
  FilmFrames& operator=(const FilmFrames&) = delete;

  int frames() const { return frames_; }
  double time_s(int k) const { return t0_s_ + k * frame_dt_s_; }
  double frame_dt_s() const { return frame_dt_s_; }
  int first_cycle() const { return first_cycle_; }
  int last_cycle() const { return last_cycle_; }
  double speedup() const { return speedup_; }  // run seconds per second at the film's fps
  // The state at t_s (interpolated between recorded states; the last one
  // after them), with the ghost of setup() for it.
  const mjData* Pose(double t_s);
  FrameSetup& setup() { return setup_; }

 private:
  void SetUpCamera(const FilmConfig& config, OffscreenRenderer& renderer);

  FilmedRun run_;
  bool ghost_;
  int frames_ = 0, first_cycle_ = 0, last_cycle_ = 0;
  double frame_dt_s_ = 0.0, t0_s_ = 0.0, speedup_ = 0.0, ideal_length_m_ = 0.0;
  DataPtr data_;
  FrameSetup setup_;
};

// Throws FieldError naming width_px/height_px and the model's
// offscreen buffer if the frames do not fit it (checked before a run so a
// long run does not end in this error).
void CheckFilmFits(const mjModel* m, const FilmConfig& config);

// Films `run` into out_path. Throws FieldError naming the field for bad
// options (FilmConfig's) or cycles the run does not have, for a run without
// states ("states") or period ("period_s", "cycles"), std::runtime_error naming
// the file if it cannot be written; nothing is left behind then.
FilmSummary FilmRun(const FilmedRun& run, const FilmConfig& config, const std::string& out_path,
                    const FilmProgress& progress = {});

// Runs the scenario once (SimulateScenario), hands the result to
// `before_filming` (if set), and films the run from its recorded states
// into video_path; the frame size is checked against the model as the run
// starts, so a bad size does not wait for the run. Returns the run's
// result; *summary (if given) gets the film's; `observer` (if set) sees
// every recorded sample of the run, `heartbeat` the time between them.
ClosedLoopResult SimulateAndFilmScenario(
    const ScenarioConfig& scenario, const FilmConfig& config, const std::string& video_path,
    const std::function<void(const ClosedLoopResult&)>& before_filming = {},
    const FilmProgress& progress = {}, FilmSummary* summary = nullptr,
    const SampleObserver& observer = {}, const RunHeartbeat& heartbeat = {});

// The ghost of a closed-loop scenario: its travelling wave y(x, t)
// (sim/core/waveform.h), times the references' start ramp.
std::function<double(double x_m, double t_s)> ScenarioIdealShape(const ScenarioConfig& scenario);

// Overlay rows of a closed-loop run: controller (with its clamp) and
// actuation.
std::vector<std::array<std::string, 2>> ClosedLoopOverlayRows(const ScenarioConfig& scenario);

}  // namespace ipmc
