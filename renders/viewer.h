// An interactive window on MuJoCo's own renderer (GLFW): one or more runs
// side by side, each drawn from its recorded states exactly as a film's
// frame is (renders/swim_film.h FilmFrames: camera, ghost, tip trails,
// grid and scale bar, time and net displacement), all at one simulated
// time; or a scenario run live, shown as its states arrive.
//
// Time. The window shows every panel at the same simulated time t. Playing
// advances t by `speed` run seconds per second of wall time (by default
// the film's: fps x period / frames_per_cycle, 25 x real time for the
// paper's run), or, under --script, by speed / fps per drawn frame, so a
// script reaches the same frames every time. Stepping moves t to the next
// or previous frame of the first panel's film (frames_per_cycle per
// cycle). The trails at t are those the film shows at its frame there:
// the tip positions of the film's frames before t, so a frame reached by
// stepping, scrubbing or playing looks the same.
//
// Camera: drag with the left button to pan, with the right button to turn
// (azimuth, elevation), scroll to zoom; every panel moves together.
//
// Script: a comma-separated list of actions, one per drawn frame, each a
// key's name as ViewerKeys() lists it (`space`, `right`, `h`, ...),
// optionally repeated as NAME*N, or `shot:FILE.png` (the window's image
// as PNG), `wait:N` (N frames with no action), `scroll:N` (zoom N notches),
// `drag:DX:DY` (pan by pixels). After the last action the window stays
// open for the keys, unless the script ends with `q`.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "renders/swim_film.h"
#include "sim/core/scenario.h"

namespace ipmc {

struct ViewerConfig {
  FilmConfig film;      // each panel's image (width, height), camera, trails, ghost, grid
  double speed = 0.0;   // run seconds per second; 0: the film's (fps x frame time)
  bool paused = false;  // start paused
  std::string script;   // actions, one per drawn frame (above)
  // Throws FieldError naming the option (speed, script).
  void Validate() const;
};

// A key of the window and what it does, as `view --help` and the window's
// key panel list them.
struct ViewerKey {
  const char* key;
  const char* action;
};
const std::vector<ViewerKey>& ViewerKeys();
// The keys as lines for a help text.
std::string ViewerKeysText();

// A scenario run in a thread of its own for the window, from which the
// window takes the states as they are recorded. Stops the run when
// destroyed.
class LiveRun {
 public:
  explicit LiveRun(const ScenarioConfig& scenario);
  ~LiveRun();
  LiveRun(const LiveRun&) = delete;
  LiveRun& operator=(const LiveRun&) = delete;

  // Waits for the first recorded state; then the run's model is there.
  // Throws the run's error if it failed before.
  void WaitForStart();
  const mjModel* model() const;
  const ScenarioConfig& scenario() const;
  // Appends the states recorded since the last call to *states.
  void TakeStates(RecordedStates* states);
  bool finished() const;
  std::string error() const;  // "" unless the run failed
  double duration_s() const { return duration_s_; }

 private:
  struct Shared;
  std::unique_ptr<Shared> shared_;
  double duration_s_ = 0.0;
};

// What a panel shows: a run read back from its output directory
// (LoadRunRecording) or a live one; `title` names it in the overlay when
// there are several panels.
struct ViewedRun {
  std::string title;
  std::unique_ptr<RunRecording> recording;
  std::unique_ptr<LiveRun> live;
};

// Opens the window and runs it until it is closed (Esc, q, the window's
// close button, or a script's q); returns 0. Throws std::runtime_error
// with one line if there is no display ("view: no display ...") or GL,
// FieldError for bad options.
int RunViewer(std::vector<ViewedRun>& runs, const ViewerConfig& config);

}  // namespace ipmc
