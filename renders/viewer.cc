#include "renders/viewer.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "renders/frame_decor.h"
#include "renders/offscreen_renderer.h"
#include "renders/video.h"
#include "sim/runs/closed_loop_run.h"

namespace ipmc {
namespace {

constexpr double kDegToRad = kPi / 180.0;
constexpr double kMaxSpeed = 1e6;           // run seconds per second
constexpr double kZoomPerNotch = 1.1;       // view width factor per scroll notch
constexpr double kTurn_deg_per_px = 0.3;    // right-button drag
constexpr int kMaxScriptRepeat = 100000;
constexpr double kMaxWallStep_s = 0.1;      // a stalled frame does not jump the clock

const std::vector<ViewerKey> kKeys = {
    {"space", "play / pause"},
    {"right", "next frame (pauses)"},
    {"left", "previous frame (pauses)"},
    {"pagedown", "next cycle"},
    {"pageup", "previous cycle"},
    {"home", "first frame"},
    {"end", "last frame (live: the newest state)"},
    {"up", "twice as fast"},
    {"down", "half as fast"},
    {"g", "ghost on / off"},
    {"t", "trails on / off"},
    {"c", "camera back to the start"},
    {"h", "this key panel on / off"},
    {"s", "screenshot view_NNNN.png"},
    {"q", "quit (also Esc)"},
};

[[noreturn]] void BadOption(const std::string& field, const std::string& range,
                            const std::string& got) {
  throw FieldError("view: --" + field + " must be " + range + " (got " + got + ")", "--" + field,
                   range);
}

std::string KeyName(int key) {
  switch (key) {
    case GLFW_KEY_SPACE: return "space";
    case GLFW_KEY_RIGHT: return "right";
    case GLFW_KEY_LEFT: return "left";
    case GLFW_KEY_UP: return "up";
    case GLFW_KEY_DOWN: return "down";
    case GLFW_KEY_PAGE_UP: return "pageup";
    case GLFW_KEY_PAGE_DOWN: return "pagedown";
    case GLFW_KEY_HOME: return "home";
    case GLFW_KEY_END: return "end";
    case GLFW_KEY_ESCAPE: return "q";
    default: break;
  }
  if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) return std::string(1, static_cast<char>('a' + key - GLFW_KEY_A));
  return "";
}

bool IsKey(const std::string& name) {
  return std::any_of(kKeys.begin(), kKeys.end(), [&](const ViewerKey& k) { return name == k.key; });
}

// The script's actions, one per frame, repetitions expanded.
std::deque<std::string> ParseScript(const std::string& script) {
  std::deque<std::string> actions;
  size_t start = 0;
  while (start < script.size()) {
    size_t end = script.find(',', start);
    if (end == std::string::npos) end = script.size();
    std::string item = script.substr(start, end - start);
    start = end + 1;
    if (item.empty()) continue;
    int repeat = 1;
    const size_t star = item.find('*');
    if (star != std::string::npos) {
      const std::optional<long> value = ParseInteger(item.substr(star + 1));
      if (!value || *value < 1 || *value > kMaxScriptRepeat) {
        BadOption("script", "actions NAME or NAME*N with N in [1, 100000]", item);
      }
      repeat = static_cast<int>(*value);
      item = item.substr(0, star);
    }
    const std::string head = item.substr(0, item.find(':'));
    const bool with_argument = item.find(':') != std::string::npos;
    const bool known = with_argument ? (head == "shot" || head == "wait" || head == "scroll" ||
                                        head == "drag")
                                     : IsKey(item);
    if (!known) {
      BadOption("script", "a list of keys (view --help) or shot:FILE, wait:N, scroll:N, drag:DX:DY",
                item);
    }
    if (head == "wait") {
      const std::optional<long> frames = ParseInteger(item.substr(5));
      if (!frames || *frames < 0 || *frames > kMaxScriptRepeat) {
        BadOption("script", "wait:N with N in [0, 100000]", item);
      }
      for (long k = 0; k < *frames * repeat; ++k) actions.push_back("wait");
      continue;
    }
    for (int k = 0; k < repeat; ++k) actions.push_back(item);
  }
  return actions;
}

}  // namespace

const std::vector<ViewerKey>& ViewerKeys() { return kKeys; }

std::string ViewerKeysText() {
  std::string text = "Keys in the window:\n";
  for (const ViewerKey& key : kKeys) {
    char line[96];
    std::snprintf(line, sizeof(line), "  %-9s %s\n", key.key, key.action);
    text += line;
  }
  text += "Mouse: drag (left button) to pan, drag (right button) to turn, scroll to zoom.\n";
  return text;
}

void ViewerConfig::Validate() const {
  film.Validate();
  if (!(speed >= 0.0 && speed <= kMaxSpeed)) {
    BadOption("speed", "in [0, 1e6] (0: the film's)", FormatShortest(speed));
  }
  ParseScript(script);
}

// ---- a live run ----------------------------------------------------------

struct LiveRun::Shared {
  ScenarioConfig scenario;
  mutable std::mutex mutex;
  std::condition_variable started;
  ModelPtr model;
  RecordedStates states;  // recorded and not yet taken
  bool finished = false;
  std::string error;
  std::atomic<bool> stop{false};
  std::thread thread;
};

namespace {
struct StopLiveRun {};
}  // namespace

LiveRun::LiveRun(const ScenarioConfig& scenario) : shared_(std::make_unique<Shared>()) {
  shared_->scenario = scenario;
  shared_->scenario.output.dir.clear();
  duration_s_ = scenario.run.cycles / std::abs(scenario.waveform.frequency_Hz);
  Shared* s = shared_.get();
  s->thread = std::thread([s] {
    const auto record = [s](const mjModel* m, const mjData* d, const ClosedLoopSample&) {
      if (s->stop) throw StopLiveRun();
      std::lock_guard<std::mutex> lock(s->mutex);
      if (!s->model) {
        s->model.reset(mj_copyModel(nullptr, m));
        s->states.columns = QposColumns(m);
        s->started.notify_all();
      }
      s->states.t_s.push_back(d->time);
      s->states.qpos.emplace_back(d->qpos, d->qpos + m->nq);
    };
    std::string error;
    try {
      SimulateScenario(s->scenario, record);
    } catch (const StopLiveRun&) {
    } catch (const std::exception& failure) {
      error = failure.what();
    }
    std::lock_guard<std::mutex> lock(s->mutex);
    s->finished = true;
    s->error = error;
    s->started.notify_all();
  });
}

LiveRun::~LiveRun() {
  shared_->stop = true;
  if (shared_->thread.joinable()) shared_->thread.join();
}

void LiveRun::WaitForStart() {
  std::unique_lock<std::mutex> lock(shared_->mutex);
  shared_->started.wait(lock, [this] { return shared_->model || shared_->finished; });
  if (!shared_->model) throw std::runtime_error(shared_->error.empty() ? "view: the run stopped"
                                                                       : shared_->error);
}

const mjModel* LiveRun::model() const { return shared_->model.get(); }

const ScenarioConfig& LiveRun::scenario() const { return shared_->scenario; }

void LiveRun::TakeStates(RecordedStates* states) {
  std::lock_guard<std::mutex> lock(shared_->mutex);
  if (states->columns.empty()) states->columns = shared_->states.columns;
  for (size_t k = 0; k < shared_->states.t_s.size(); ++k) {
    states->t_s.push_back(shared_->states.t_s[k]);
    states->qpos.push_back(std::move(shared_->states.qpos[k]));
  }
  shared_->states.t_s.clear();
  shared_->states.qpos.clear();
}

bool LiveRun::finished() const {
  std::lock_guard<std::mutex> lock(shared_->mutex);
  return shared_->finished;
}

std::string LiveRun::error() const {
  std::lock_guard<std::mutex> lock(shared_->mutex);
  return shared_->error;
}

// ---- the window ----------------------------------------------------------

namespace {

// One run in its part of the window.
struct Panel {
  ViewedRun* source = nullptr;
  RecordedStates live_states;  // a live run's states so far
  FilmedRun run;
  std::unique_ptr<OffscreenRenderer> renderer;
  std::unique_ptr<FilmFrames> frames;
  CameraSetup start_camera;
  int trail_frames = 0;
  double last_time_s() const { return run.states->t_s.back(); }
};

struct GlfwSession {
  GlfwSession() {
    glfwSetErrorCallback([](int, const char*) {});
    if (!glfwInit()) {
      throw std::runtime_error(
          "view: no display: cannot open a window (DISPLAY is not set or its X server does not "
          "answer; ipmc-swim render writes a video without one)");
    }
  }
  ~GlfwSession() { glfwTerminate(); }
};

class Viewer {
 public:
  Viewer(std::vector<ViewedRun>& runs, const ViewerConfig& config);
  ~Viewer();
  void Loop();

 private:
  void OpenWindow(int width, int height);
  void AddPanel(ViewedRun& source, int index);
  void Apply(const std::string& action);
  void Advance(double wall_s);
  void DrawFrame();
  void DrawPanel(Panel& panel);
  void Screenshot(const std::string& path);
  void StepFrames(int frames);
  double EndTime_s() const;
  double PlannedEnd_s() const;
  void WaitForLiveStates();
  void SetSpeed(double speed);
  void UpdateCamera();

  static void OnKey(GLFWwindow* w, int key, int, int action, int);
  static void OnButton(GLFWwindow* w, int button, int action, int);
  static void OnMove(GLFWwindow* w, double x, double y);
  static void OnScroll(GLFWwindow* w, double, double dy);

  const ViewerConfig& config_;
  GlfwSession glfw_;
  GLFWwindow* window_ = nullptr;
  int width_ = 0, height_ = 0;
  std::vector<std::unique_ptr<Panel>> panels_;
  std::deque<std::string> script_, pending_;
  bool scripted_ = false;
  double t_s_ = 0.0, speed_ = 1.0;
  bool playing_ = true, help_ = true, ghost_ = true, trails_ = true;
  // Camera changes from the panels' start: zoom factor of the view width,
  // pan [m], turn [deg].
  double zoom_ = 1.0, pan_m_[2] = {0, 0}, azimuth_deg_ = 0.0, elevation_deg_ = 0.0;
  int button_ = -1;
  double mouse_[2] = {0, 0};
  int screenshots_ = 0;
};

Viewer::Viewer(std::vector<ViewedRun>& runs, const ViewerConfig& config) : config_(config) {
  if (runs.empty()) throw FieldError("view: nothing to show", "inputs", "a run or a scenario");
  script_ = ParseScript(config.script);
  scripted_ = !config.script.empty();
  OpenWindow(config.film.width * static_cast<int>(runs.size()), config.film.height);
  for (size_t i = 0; i < runs.size(); ++i) AddPanel(runs[i], static_cast<int>(i));
  const FilmFrames& first = *panels_.front()->frames;
  t_s_ = first.time_s(0);
  SetSpeed(config.speed > 0.0 ? config.speed : first.speedup());
  playing_ = !config.paused;
  ghost_ = config.film.ghost;
}

Viewer::~Viewer() {
  if (!window_) return;
  glfwMakeContextCurrent(window_);
  panels_.clear();  // their GL objects go with the window's context current
  glfwDestroyWindow(window_);
}

void Viewer::OpenWindow(int width, int height) {
  glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
  glfwWindowHint(GLFW_SAMPLES, 0);  // as the film's frames (offscreen_renderer.cc)
  window_ = glfwCreateWindow(width, height, "ipmc-swim view", nullptr, nullptr);
  if (!window_) throw std::runtime_error("view: the display cannot open a GL window");
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(scripted_ ? 0 : 1);
  glfwGetFramebufferSize(window_, &width_, &height_);
  glfwSetWindowUserPointer(window_, this);
  glfwSetKeyCallback(window_, OnKey);
  glfwSetMouseButtonCallback(window_, OnButton);
  glfwSetCursorPosCallback(window_, OnMove);
  glfwSetScrollCallback(window_, OnScroll);
}

void Viewer::AddPanel(ViewedRun& source, int index) {
  auto panel = std::make_unique<Panel>();
  panel->source = &source;
  if (source.live) {
    source.live->WaitForStart();
    source.live->TakeStates(&panel->live_states);
    const ScenarioConfig& scenario = source.live->scenario();
    panel->run.model = source.live->model();
    panel->run.states = &panel->live_states;
    panel->run.period_s = 1.0 / std::abs(scenario.waveform.frequency_Hz);
    panel->run.cycles = scenario.run.cycles;
    panel->run.overlay_rows = ClosedLoopOverlayRows(scenario);
    panel->run.ideal_y_m = ScenarioIdealShape(scenario);
  } else {
    panel->run = source.recording->View();
  }
  if (!source.title.empty()) panel->run.overlay_rows.push_back({"run", source.title});
  RendererOptions options = FilmRendererOptions(config_.film);
  options.window = true;
  options.left_px = index * config_.film.width;
  options.bottom_px = height_ - config_.film.height;
  panel->trail_frames = options.trail_length;
  panel->renderer = std::make_unique<OffscreenRenderer>(panel->run.model, config_.film.width,
                                                        config_.film.height, options);
  panel->frames = std::make_unique<FilmFrames>(panel->run, config_.film, *panel->renderer);
  panel->start_camera = panel->frames->setup().camera;
  panels_.push_back(std::move(panel));
}

double Viewer::EndTime_s() const {
  double end = 0.0;
  for (const auto& panel : panels_) end = std::max(end, panel->last_time_s());
  return end;
}

// Where the runs will end: a live run's full length.
double Viewer::PlannedEnd_s() const {
  double end = 0.0;
  for (const auto& panel : panels_) {
    const LiveRun* live = panel->source->live.get();
    end = std::max(end, live && !live->finished() ? live->duration_s() : panel->last_time_s());
  }
  return end;
}

// Under a script, a screenshot waits until every live run has reached the
// time shown (or ended), so that a script's pictures do not depend on how
// fast the runs go.
void Viewer::WaitForLiveStates() {
  for (auto& panel : panels_) {
    LiveRun* live = panel->source->live.get();
    while (live && panel->last_time_s() < t_s_ - 1e-9 && !live->finished()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      live->TakeStates(&panel->live_states);
    }
    if (live) live->TakeStates(&panel->live_states);
  }
}

void Viewer::SetSpeed(double speed) {
  speed_ = std::clamp(speed, 1e-6, kMaxSpeed);
  for (auto& panel : panels_) {
    panel->frames->setup().overlay.rows.front() = {"playback", PlaybackSpeedText(speed_)};
  }
}

void Viewer::StepFrames(int frames) {
  const FilmFrames& first = *panels_.front()->frames;
  const double dt = first.frame_dt_s();
  const double k = std::floor((t_s_ - first.time_s(0)) / dt + 1e-6);
  t_s_ = first.time_s(0) + (k + frames) * dt;
  t_s_ = std::clamp(t_s_, first.time_s(0), PlannedEnd_s());
  playing_ = false;
}

void Viewer::Apply(const std::string& action) {
  const FilmFrames& first = *panels_.front()->frames;
  const int per_cycle = static_cast<int>(std::lround(panels_.front()->run.period_s / first.frame_dt_s()));
  if (action == "space") {
    playing_ = !playing_;
    if (playing_ && t_s_ >= EndTime_s()) t_s_ = first.time_s(0);
  } else if (action == "right") {
    StepFrames(1);
  } else if (action == "left") {
    StepFrames(-1);
  } else if (action == "pagedown") {
    StepFrames(per_cycle);
  } else if (action == "pageup") {
    StepFrames(-per_cycle);
  } else if (action == "home") {
    t_s_ = first.time_s(0);
  } else if (action == "end") {
    t_s_ = EndTime_s();
  } else if (action == "up") {
    SetSpeed(2.0 * speed_);
  } else if (action == "down") {
    SetSpeed(0.5 * speed_);
  } else if (action == "g") {
    ghost_ = !ghost_;
  } else if (action == "t") {
    trails_ = !trails_;
  } else if (action == "c") {
    zoom_ = 1.0;
    pan_m_[0] = pan_m_[1] = 0.0;
    azimuth_deg_ = elevation_deg_ = 0.0;
  } else if (action == "h") {
    help_ = !help_;
  } else if (action == "s") {
    char name[32];
    std::snprintf(name, sizeof(name), "view_%04d.png", screenshots_++);
    Screenshot(name);
  } else if (action == "q") {
    glfwSetWindowShouldClose(window_, GLFW_TRUE);
  } else if (action.rfind("shot:", 0) == 0) {
    Screenshot(action.substr(5));
  } else if (action.rfind("scroll:", 0) == 0) {
    const std::optional<double> notches = ParseDouble(action.substr(7));
    if (notches) zoom_ *= std::pow(kZoomPerNotch, -*notches);
  } else if (action.rfind("drag:", 0) == 0) {
    const std::string args = action.substr(5);
    const size_t colon = args.find(':');
    const std::optional<double> dx = ParseDouble(args.substr(0, colon));
    const std::optional<double> dy =
        colon == std::string::npos ? std::nullopt : ParseDouble(args.substr(colon + 1));
    if (dx && dy) {
      const Panel& panel = *panels_.front();
      const double px_per_m = panel.renderer->PixelsPerMetre(panel.frames->setup().camera);
      pan_m_[0] -= *dx / px_per_m;
      pan_m_[1] += *dy / px_per_m;
    }
  }
}

// The panels' cameras: their start, zoomed, panned and turned.
void Viewer::UpdateCamera() {
  for (auto& panel : panels_) {
    CameraSetup camera = panel->start_camera;
    const double view_m = config_.film.width / panel->renderer->PixelsPerMetre(camera);
    camera.view_width_m = std::clamp(view_m * zoom_, 1e-5, 10.0);
    // Pan along the screen's axes as seen from above (+x right, +y up at
    // the start's azimuth of 90 deg).
    const double az = camera.azimuth_deg * kDegToRad;
    const double right[2] = {std::sin(az), -std::cos(az)}, up[2] = {std::cos(az), std::sin(az)};
    for (int i = 0; i < 2; ++i) {
      const double shift = pan_m_[0] * right[i] + pan_m_[1] * up[i];
      if (camera.follow) {
        camera.follow_offset_m[i] += shift;
      } else {
        camera.lookat_m[i] += shift;
      }
    }
    camera.azimuth_deg = std::clamp(camera.azimuth_deg + azimuth_deg_, -360.0, 360.0);
    camera.elevation_deg = std::clamp(camera.elevation_deg + elevation_deg_, -90.0, -5.0);
    panel->frames->setup().camera = camera;
  }
}

void Viewer::Advance(double wall_s) {
  for (auto& panel : panels_) {
    if (panel->source->live) panel->source->live->TakeStates(&panel->live_states);
  }
  if (!playing_) return;
  const double end = EndTime_s();
  t_s_ += speed_ * wall_s;
  if (t_s_ >= end) {
    t_s_ = end;
    // A finished run stops at its end; a live one waits for its states.
    const bool growing = std::any_of(panels_.begin(), panels_.end(), [](const auto& panel) {
      return panel->source->live && !panel->source->live->finished();
    });
    if (!growing) playing_ = false;
  }
}

void Viewer::DrawPanel(Panel& panel) {
  FilmFrames& frames = *panel.frames;
  OffscreenRenderer& renderer = *panel.renderer;
  // The trails the film shows at its frame k (frames k - L + 1 .. k).
  const double dt = frames.frame_dt_s();
  const int k = static_cast<int>(std::floor((t_s_ - frames.time_s(0)) / dt + 1e-6));
  renderer.Reset();
  if (trails_) {
    for (int j = std::max(0, k - panel.trail_frames + 1); j < k; ++j) {
      renderer.AppendTrail(frames.Pose(frames.time_s(j)));
    }
  }
  const mjData* d = frames.Pose(t_s_);
  FrameSetup& setup = frames.setup();
  std::vector<std::array<double, 3>> ghost;
  if (!ghost_) setup.ghost_m.swap(ghost);
  std::vector<std::array<std::string, 2>>& rows = setup.overlay.rows;
  const size_t fixed_rows = rows.size();
  if (panel.source->live) {
    const LiveRun& live = *panel.source->live;
    char text[96];
    std::snprintf(text, sizeof(text), "%.1f s of %.0f s%s", panel.last_time_s(), live.duration_s(),
                  live.finished() ? (live.error().empty() ? ", done" : ", failed") : "");
    rows.push_back({"simulated", text});
  }
  renderer.Draw(d, setup);
  rows.resize(fixed_rows);
}

void Viewer::DrawFrame() {
  glfwMakeContextCurrent(window_);
  UpdateCamera();
  for (auto& panel : panels_) DrawPanel(*panel);
  if (help_) {
    std::vector<std::array<std::string, 2>> rows;
    char state[96];
    std::snprintf(state, sizeof(state), "%s, %s", playing_ ? "playing" : "paused",
                  PlaybackSpeedText(speed_).c_str());
    rows.push_back({"view", state});
    for (const ViewerKey& key : kKeys) rows.push_back({key.key, key.action});
    rows.push_back({"mouse", "drag: pan, right drag: turn, scroll: zoom"});
    DrawTable(panels_.back()->renderer->Canvas(), rows, /*right=*/true);
  }
}

void Viewer::Screenshot(const std::string& path) {
  if (scripted_) WaitForLiveStates();
  DrawFrame();
  std::vector<unsigned char> pixels(static_cast<size_t>(width_) * height_ * 3);
  mjr_readPixels(pixels.data(), nullptr, {0, 0, width_, height_},
                 panels_.front()->renderer->Canvas().con);
  std::vector<unsigned char> rgb(pixels.size());
  const size_t row = static_cast<size_t>(width_) * 3;
  for (int y = 0; y < height_; ++y) {
    std::copy_n(pixels.data() + row * (height_ - 1 - y), row, rgb.data() + row * y);
  }
  WritePng(path, rgb, width_, height_);
  std::printf("view: %s at %.4f s\n", path.c_str(), t_s_);
  std::fflush(stdout);
}

void Viewer::Loop() {
  auto last = std::chrono::steady_clock::now();
  while (!glfwWindowShouldClose(window_)) {
    glfwPollEvents();
    const auto now = std::chrono::steady_clock::now();
    const double wall_s = std::chrono::duration<double>(now - last).count();
    last = now;
    if (scripted_) {
      if (!script_.empty()) {
        const std::string action = script_.front();
        script_.pop_front();
        if (action != "wait") Apply(action);
      }
      Advance(1.0 / config_.film.fps);
    } else {
      Advance(std::min(wall_s, kMaxWallStep_s));
    }
    while (!pending_.empty()) {
      Apply(pending_.front());
      pending_.pop_front();
    }
    if (glfwWindowShouldClose(window_)) break;
    DrawFrame();
    glfwSwapBuffers(window_);
  }
}

Viewer* Of(GLFWwindow* window) { return static_cast<Viewer*>(glfwGetWindowUserPointer(window)); }

void Viewer::OnKey(GLFWwindow* w, int key, int, int action, int) {
  if (action == GLFW_RELEASE) return;
  const std::string name = KeyName(key);
  if (IsKey(name)) Of(w)->pending_.push_back(name);
}

void Viewer::OnButton(GLFWwindow* w, int button, int action, int) {
  Viewer* v = Of(w);
  v->button_ = action == GLFW_PRESS ? button : -1;
  glfwGetCursorPos(w, &v->mouse_[0], &v->mouse_[1]);
}

void Viewer::OnMove(GLFWwindow* w, double x, double y) {
  Viewer* v = Of(w);
  const double dx = x - v->mouse_[0], dy = y - v->mouse_[1];
  v->mouse_[0] = x;
  v->mouse_[1] = y;
  if (v->button_ == GLFW_MOUSE_BUTTON_LEFT) {
    char drag[64];
    std::snprintf(drag, sizeof(drag), "drag:%.17g:%.17g", dx, dy);
    v->pending_.push_back(drag);
  } else if (v->button_ == GLFW_MOUSE_BUTTON_RIGHT) {
    v->azimuth_deg_ -= kTurn_deg_per_px * dx;
    // (UpdateCamera keeps the sum within [-90, -5])
    v->elevation_deg_ = std::clamp(v->elevation_deg_ + kTurn_deg_per_px * dy, -85.0, 85.0);
  }
}

void Viewer::OnScroll(GLFWwindow* w, double, double dy) {
  char scroll[48];
  std::snprintf(scroll, sizeof(scroll), "scroll:%.17g", dy);
  Of(w)->pending_.push_back(scroll);
}

}  // namespace

int RunViewer(std::vector<ViewedRun>& runs, const ViewerConfig& config) {
  config.Validate();
  Viewer viewer(runs, config);
  viewer.Loop();
  for (const ViewedRun& run : runs) {
    if (run.live && !run.live->error().empty()) throw std::runtime_error(run.live->error());
  }
  return 0;
}

}  // namespace ipmc
