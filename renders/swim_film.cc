#include "renders/swim_film.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "renders/offscreen_renderer.h"
#include "renders/video.h"
#include "sim/core/simulation.h"
#include "sim/core/waveform.h"
#include "sim/io/files.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/runs/output.h"

namespace ipmc {
namespace {

constexpr int kMaxTrailFrames = 10000;
// A wave cycle filmed in more frames than this is a mistake (1e4 frames
// are 7 min at 25 fps) and would hold its samples in memory.
constexpr int kMaxFramesPerCycle = 10000;
constexpr double kMaxView_mm = 10000.0;
constexpr double kMaxStripThickness_mm = 10.0;
// Fixed camera: margin around the filmed body, relative to its larger side.
constexpr double kFitMargin = 0.06;
// Follow camera: the rest length over the image width.
constexpr double kFollowBodyFill = 0.6;
// Points of the ghost polyline along the body.
constexpr int kGhostPoints = 64;
constexpr int kRootBody = 1;

template <typename T>
[[noreturn]] void ThrowOption(const std::string& field, const std::string& requirement, T value) {
  std::ostringstream msg;
  msg << "video: " << field << " must be " << requirement << " (got " << value << ")";
  throw FieldError(msg.str(), field, requirement);
}

std::string FramePath(const std::string& dir, int index) {
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%05d.png", index);
  return (std::filesystem::path(dir) / name).string();
}

// The PNGs written so far; removed unless the film completes.
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

// The head's frame in the state of d (kinematics done): origin at hinge
// j1's anchor (the root body's origin if there is no j1), axes the root
// body's x and y.
struct HeadFrame {
  double origin[2], x_axis[2], y_axis[2];
  HeadFrame(const mjModel* m, const mjData* d) {
    const int j1 = mj_name2id(m, mjOBJ_JOINT, "j1");
    const mjtNum* p = j1 >= 0 ? d->xanchor + 3 * j1 : d->xpos + 3 * kRootBody;
    const mjtNum* r = d->xmat + 9 * kRootBody;
    origin[0] = p[0];
    origin[1] = p[1];
    x_axis[0] = r[0];
    x_axis[1] = r[3];
    y_axis[0] = r[1];
    y_axis[1] = r[4];
  }
};

// Length of the ideal shape: from j1 to the last tip site along the head's
// axis at rest (0 if the model has no tip sites).
double IdealLength_m(const mjModel* m, mjData* d) {
  int last_tip = -1;
  for (int k = 1;; ++k) {
    const int site = mj_name2id(m, mjOBJ_SITE, ("tip" + std::to_string(k)).c_str());
    if (site < 0) break;
    last_tip = site;
  }
  if (last_tip < 0) return 0.0;
  mju_copy(d->qpos, m->qpos0, m->nq);
  mj_kinematics(m, d);
  const HeadFrame head(m, d);
  const mjtNum* tip = d->site_xpos + 3 * last_tip;
  return (tip[0] - head.origin[0]) * head.x_axis[0] + (tip[1] - head.origin[1]) * head.x_axis[1];
}

std::vector<std::array<double, 3>> Ghost(const FilmedRun& run, const mjModel* m, const mjData* d,
                                         double length_m, double t_s) {
  std::vector<std::array<double, 3>> points;
  if (!run.ideal_y_m || length_m <= 0.0) return points;
  const HeadFrame head(m, d);
  for (int k = 0; k < kGhostPoints; ++k) {
    const double x = length_m * k / (kGhostPoints - 1);
    const double y = run.ideal_y_m(x, t_s);
    points.push_back({head.origin[0] + x * head.x_axis[0] + y * head.y_axis[0],
                      head.origin[1] + x * head.x_axis[1] + y * head.y_axis[1], 0.0});
  }
  return points;
}

}  // namespace

std::string PlaybackSpeedText(double factor) {
  char text[48];
  std::snprintf(text, sizeof(text), "%.3g x real time", factor);
  return text;
}

void FilmConfig::Validate() const {
  if (width <= 0 || width % 2 != 0) ThrowOption("width_px", "positive and even", width);
  if (height <= 0 || height % 2 != 0) ThrowOption("height_px", "positive and even", height);
  if (!(fps > 0.0 && fps <= 1000.0)) ThrowOption("fps", "in (0, 1000]", fps);
  if (frames_per_cycle < 1 || frames_per_cycle > kMaxFramesPerCycle) {
    ThrowOption("frames_per_cycle", "in [1, " + std::to_string(kMaxFramesPerCycle) + "]",
                frames_per_cycle);
  }
  if (start_cycle < 1) ThrowOption("start_cycle", ">= 1", start_cycle);
  if (cycles < 0) ThrowOption("cycles", ">= 1", cycles);
  if (trail_frames < -1 || trail_frames > kMaxTrailFrames) {
    ThrowOption("trail_frames",
                "in [0, " + std::to_string(kMaxTrailFrames) + "] (or -1: one cycle)",
                trail_frames);
  }
  if (!(view_mm >= 0.0 && view_mm <= kMaxView_mm)) {
    ThrowOption("view_mm", "in (0, 10000] (or 0: fit)", view_mm);
  }
  if (!center_mm.empty()) {
    if (center_mm.size() != 2) ThrowOption("center_mm", "two numbers X,Y", center_mm.size());
    for (double v : center_mm) {
      if (!std::isfinite(v)) ThrowOption("center_mm", "finite", v);
    }
    if (camera == FilmCamera::kFollow) {
      throw FieldError("video: center_mm is for camera fixed (follow looks at the centre of mass)",
                       "center_mm", "camera fixed");
    }
  }
  if (!(elevation_deg >= -90.0 && elevation_deg <= -5.0)) {
    ThrowOption("elevation_deg", "in [-90, -5] (-90: top-down)", elevation_deg);
  }
  if (!(std::abs(azimuth_deg) <= 360.0)) ThrowOption("azimuth_deg", "in [-360, 360]", azimuth_deg);
  if (strip_thickness_mm &&
      !(*strip_thickness_mm >= 0.0 && *strip_thickness_mm <= kMaxStripThickness_mm)) {
    ThrowOption("strip_thickness_mm", "in [0, 10] (0: the model's own)", *strip_thickness_mm);
  }
}

void CheckFilmFits(const mjModel* m, const FilmConfig& config) {
  try {
    OffscreenRenderer::CheckImageSize(m, config.width, config.height);
  } catch (const FieldError& error) {
    throw FieldError(std::string("video: width_px/height_px: ") + error.what(),
                     error.field() == "height" ? "height_px" : "width_px", error.allowed());
  }
}

FilmFrames::FilmFrames(const FilmedRun& run, const FilmConfig& config,
                       OffscreenRenderer& renderer)
    : run_(run), ghost_(config.ghost) {
  config.Validate();
  if (!run.model || !run.states || run.states->empty()) {
    throw FieldError("video: no recorded states to film", "states", "recorded states");
  }
  const mjModel* m = run.model;
  if (static_cast<int>(run.states->columns.size()) != m->nq) {
    throw FieldError("video: the recorded states do not match the model", "states",
                     "one column per qpos of the model");
  }
  if (!(run.period_s > 0.0) || run.cycles < 1) {
    throw FieldError("video: the run has no wave period or no cycle",
                     run.period_s > 0.0 ? "cycles" : "period_s", "period_s > 0 and cycles >= 1");
  }
  first_cycle_ = config.start_cycle;
  last_cycle_ = config.cycles == 0 ? run.cycles : first_cycle_ + config.cycles - 1;
  if (first_cycle_ > run.cycles) {
    throw FieldError("video: start_cycle " + std::to_string(first_cycle_) +
                         " is after the run's last cycle " + std::to_string(run.cycles),
                     "start_cycle", "<= " + std::to_string(run.cycles));
  }
  if (last_cycle_ > run.cycles) {
    throw FieldError("video: cycles " + std::to_string(config.cycles) + " from cycle " +
                         std::to_string(first_cycle_) + " go past the run's last cycle " +
                         std::to_string(run.cycles),
                     "cycles", "<= " + std::to_string(run.cycles - first_cycle_ + 1));
  }
  frames_ = config.frames_per_cycle * (last_cycle_ - first_cycle_ + 1);
  frame_dt_s_ = run.period_s / config.frames_per_cycle;
  t0_s_ = (first_cycle_ - 1) * run.period_s;
  speedup_ = config.fps * frame_dt_s_;

  data_.reset(mj_makeData(m));
  if (!data_) throw std::runtime_error("video: cannot allocate mjData");
  mjData* d = data_.get();
  ideal_length_m_ = IdealLength_m(m, d);

  // Centre of mass at the run's first recorded state: the overlay's origin.
  mju_copy(d->qpos, run.states->qpos.front().data(), m->nq);
  mj_kinematics(m, d);
  mj_comPos(m, d);
  setup_.grid = config.grid;
  setup_.overlay.period_s = run.period_s;
  setup_.overlay.origin_m = {d->subtree_com[3 * kRootBody], d->subtree_com[3 * kRootBody + 1]};
  setup_.overlay.rows.push_back({"playback", PlaybackSpeedText(speedup_)});
  for (const auto& row : run.overlay_rows) setup_.overlay.rows.push_back(row);
  SetUpCamera(config, renderer);
}

void FilmFrames::SetUpCamera(const FilmConfig& config, OffscreenRenderer& renderer) {
  const mjModel* m = run_.model;
  mjData* d = data_.get();
  // The overlay's band at the top of the image, as a fraction of its height.
  const double aspect = static_cast<double>(renderer.width()) / renderer.height();
  const int overlay_lines = 3 + static_cast<int>(setup_.overlay.rows.size());
  const double band = std::min(0.5, (overlay_lines + 1.5) * renderer.overlay_line_height_px() /
                                        static_cast<double>(renderer.height()));
  CameraSetup& camera = setup_.camera;
  camera.elevation_deg = config.elevation_deg;
  camera.azimuth_deg = config.azimuth_deg;
  if (config.camera == FilmCamera::kFollow) {
    // The centre of mass in the middle of the image below the band.
    camera.follow = true;
    camera.body_fill = kFollowBodyFill;
    camera.view_width_m = config.view_mm * 1e-3;
    const double view_m = renderer.width() / renderer.PixelsPerMetre(camera);
    camera.follow_offset_m[1] = 0.5 * band * view_m / aspect;
  } else {
    // The body over every frame (and the ghost), framed below the band.
    double lo[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
    double hi[2] = {-lo[0], -lo[1]};
    const double ghost_half = 0.5 * renderer.strip_thickness_m();  // the ghost is as thick
    for (int k = 0; k < frames_; ++k) {
      const double t_s = time_s(k);
      const std::vector<double> qpos = run_.states->StateAt(m, t_s);
      mju_copy(d->qpos, qpos.data(), m->nq);
      const std::array<double, 4> box = renderer.DrawnBounds(d);
      lo[0] = std::min(lo[0], box[0]);
      hi[0] = std::max(hi[0], box[1]);
      lo[1] = std::min(lo[1], box[2]);
      hi[1] = std::max(hi[1], box[3]);
      if (ghost_) {
        mj_kinematics(m, d);
        for (const auto& p : Ghost(run_, m, d, ideal_length_m_, t_s)) {
          for (int i = 0; i < 2; ++i) {
            lo[i] = std::min(lo[i], p[i] - ghost_half);
            hi[i] = std::max(hi[i], p[i] + ghost_half);
          }
        }
      }
    }
    const double margin = kFitMargin * std::max(hi[0] - lo[0], hi[1] - lo[1]);
    double view_m = config.view_mm * 1e-3;
    if (view_m <= 0.0) {
      view_m = std::max(hi[0] - lo[0] + 2.0 * margin,
                        (hi[1] - lo[1] + 2.0 * margin) / (1.0 - band) * aspect);
    }
    camera.follow = false;
    camera.view_width_m = view_m;
    if (!config.center_mm.empty()) {
      camera.lookat_m[0] = config.center_mm[0] * 1e-3;
      camera.lookat_m[1] = config.center_mm[1] * 1e-3;
    } else {
      camera.lookat_m[0] = 0.5 * (lo[0] + hi[0]);
      camera.lookat_m[1] = 0.5 * (lo[1] + hi[1]) + 0.5 * band * view_m / aspect;
    }
    camera.lookat_m[2] = 0.0;
  }
  OffscreenRenderer::ValidateCamera(camera);
}

RendererOptions FilmRendererOptions(const FilmConfig& config) {
  RendererOptions options;
  options.trail_length = config.trail_frames < 0 ? config.frames_per_cycle : config.trail_frames;
  if (config.strip_thickness_mm) options.strip_thickness_m = *config.strip_thickness_mm * 1e-3;
  return options;
}

const mjData* FilmFrames::Pose(double t_s) {
  const mjModel* m = run_.model;
  mjData* d = data_.get();
  const std::vector<double> qpos = run_.states->StateAt(m, t_s);
  mju_copy(d->qpos, qpos.data(), m->nq);
  d->time = t_s;
  if (ghost_) {
    mj_kinematics(m, d);
    setup_.ghost_m = Ghost(run_, m, d, ideal_length_m_, t_s);
  }
  return d;
}

FilmSummary FilmRun(const FilmedRun& run, const FilmConfig& config, const std::string& out_path,
                    const FilmProgress& progress) {
  config.Validate();
  if (!run.model) throw FieldError("video: no recorded states to film", "states", "recorded states");
  CheckFilmFits(run.model, config);
  OffscreenRenderer renderer(run.model, config.width, config.height, FilmRendererOptions(config));
  FilmFrames film(run, config, renderer);

  const std::filesystem::path parent = std::filesystem::path(out_path).parent_path();
  if (!parent.empty()) EnsureDirectory(parent.string());
  if (!config.png_dir.empty()) EnsureDirectory(config.png_dir);
  Mp4Writer video(out_path, config.width, config.height, config.fps);
  PngSequence pngs(config.png_dir);
  const int frames = film.frames();
  for (int k = 0; k < frames; ++k) {
    const mjData* d = film.Pose(film.time_s(k));
    const std::vector<unsigned char> rgb = renderer.Frame(d, film.setup());
    video.AddFrame(rgb);
    pngs.Add(rgb, config.width, config.height);
    if (progress) progress(k + 1, frames);
  }
  video.Finish();
  pngs.Keep();

  FilmSummary summary;
  summary.frames = frames;
  summary.first_cycle = film.first_cycle();
  summary.last_cycle = film.last_cycle();
  summary.pixels_per_mm = renderer.PixelsPerMetre(film.setup().camera) * 1e-3;
  summary.view_width_mm = config.width / summary.pixels_per_mm;
  summary.speedup = film.speedup();
  return summary;
}

ClosedLoopResult SimulateAndFilmScenario(
    const ScenarioConfig& scenario, const FilmConfig& config, const std::string& video_path,
    const std::function<void(const ClosedLoopResult&)>& before_filming,
    const FilmProgress& progress, FilmSummary* summary, const SampleObserver& observer,
    const RunHeartbeat& heartbeat) {
  config.Validate();
  if (!config.png_dir.empty()) EnsureDirectory(config.png_dir);
  ModelPtr model;  // the run's own model, copied at t = 0
  const auto copy_model = [&](const mjModel* m, const mjData* d, const ClosedLoopSample& sample) {
    if (observer) observer(m, d, sample);
    if (model) return;
    CheckFilmFits(m, config);
    model.reset(mj_copyModel(nullptr, m));
  };
  const ClosedLoopResult result = SimulateScenario(scenario, copy_model, heartbeat);
  if (before_filming) before_filming(result);
  const FilmSummary film =
      FilmRun(ClosedLoopFilm(model.get(), result, scenario), config, video_path, progress);
  if (summary) *summary = film;
  return result;
}

FilmedRun ClosedLoopFilm(const mjModel* m, const ClosedLoopResult& result,
                         const ScenarioConfig& scenario) {
  FilmedRun run;
  run.model = m;
  run.states = &result.states;
  run.period_s = result.period_s;
  run.cycles = static_cast<int>(result.swim.per_cycle.size());
  run.overlay_rows = ClosedLoopOverlayRows(scenario);
  run.ideal_y_m = ScenarioIdealShape(scenario);
  return run;
}

FilmedRun RunRecording::View() const {
  FilmedRun run;
  run.model = model.get();
  run.states = &states;
  run.period_s = period_s;
  run.cycles = cycles;
  run.overlay_rows = overlay_rows;
  run.ideal_y_m = ideal_y_m;
  return run;
}

RunRecording LoadRunRecording(const std::string& dir) {
  const std::string summary_path = (std::filesystem::path(dir) / "summary.json").string();
  const std::string states_path = (std::filesystem::path(dir) / "states.csv").string();
  for (const std::string& path : {summary_path, states_path}) {
    if (!std::filesystem::is_regular_file(path)) {
      const std::string name = std::filesystem::path(path).filename().string();
      throw InputError(InputProblem::kMissing, {dir}, name,
                       "not a run's output directory (no " + name + ")");
    }
  }
  nlohmann::json summary;
  try {
    std::ifstream in(summary_path);
    summary = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& error) {
    throw InputError(InputProblem::kSyntax, {summary_path}, "", error.what());
  }
  const auto field = [&](const nlohmann::json& object, const char* key, const std::string& name) {
    if (!object.is_object() || !object.contains(key)) {
      throw InputError(InputProblem::kMissing, {summary_path}, name, "no field " + name);
    }
    return object.at(key);
  };
  RunRecording recording;
  const nlohmann::json inputs = field(summary, "inputs", "inputs");
  if (summary.contains("controller")) {
    // The scenario as run (with its overrides) on the model it ran, or, in
    // older summaries, its file.
    const ScenarioConfig scenario =
        inputs.contains("resolved_scenario")
            ? ScenarioOfSummary(summary_path)
            : LoadScenario(field(inputs, "scenario", "inputs.scenario").get<std::string>());
    std::string source;
    recording.model = LoadScenarioModel(scenario, &source);
    recording.overlay_rows = ClosedLoopOverlayRows(scenario);
    recording.ideal_y_m = ScenarioIdealShape(scenario);
  } else {
    recording.model = LoadModelFile(ModelOfGaitSummary(summary_path, inputs));
    recording.overlay_rows = {{"gait", field(summary, "gait", "gait").get<std::string>()}};
  }
  recording.period_s = field(summary, "period_s", "period_s").get<double>();
  recording.cycles = static_cast<int>(field(summary, "per_cycle", "per_cycle").size());
  recording.states = ReadRecordedStates(states_path, recording.model.get());
  return recording;
}

std::function<double(double, double)> ScenarioIdealShape(const ScenarioConfig& scenario) {
  const WaveformConfig wave = scenario.waveform;
  const double ramp_s = scenario.waveform.start_ramp_cycles / std::abs(wave.frequency_Hz);
  return [wave, ramp_s](double x_m, double t_s) {
    return StartRamp(t_s, ramp_s) * WaveY_um(wave, x_m * 1e3, t_s) * 1e-6;
  };
}

namespace {

// The links' values of one gain, "8.12" when every link has it, else
// "10.3/2.6/1.2" (per link, in order).
std::string LinkValues(const std::vector<double>& values) {
  std::string text;
  for (double v : values) {
    if (!text.empty()) text += "/";
    text += FormatText("%g", v);
  }
  const bool same = std::all_of(values.begin(), values.end(),
                                [&](double v) { return v == values.front(); });
  return same ? FormatText("%g", values.front()) : text;
}

}  // namespace

std::vector<std::array<std::string, 2>> ClosedLoopOverlayRows(const ScenarioConfig& scenario) {
  const ControllerScenario& c = scenario.controller;
  const bool pid = c.kind == ControllerKind::kPid;
  const bool clamp = pid ? c.pid.clamp_enabled : c.fractional.clamp_enabled;
  const double v_max = pid ? c.pid.v_max : c.fractional.v_max;
  // The gains that ran: each driven link's (its controller.link_* where
  // given). Without per-link gains every link runs the scalar keys'.
  size_t links = 1;
  for (const std::vector<double>* each :
       {&c.link_gains.kp, &c.link_gains.ki, &c.link_gains.kd, &c.link_gains.gain,
        &c.link_gains.order}) {
    links = std::max(links, each->size());
  }
  if (scenario.actuation == Actuation::kSingle) links = 1;
  std::vector<double> kp, ki, kd, gain, order;
  for (size_t q = 0; q < links; ++q) {
    const PidController::Config p = c.LinkPid(static_cast<int>(q));
    const FractionalIntegrator::Config f = c.LinkFractional(static_cast<int>(q));
    kp.push_back(p.kp), ki.push_back(p.ki), kd.push_back(p.kd);
    gain.push_back(f.gain), order.push_back(f.order);
  }
  std::string controller =
      pid ? "PID, Kp " + LinkValues(kp) + ", Ki " + LinkValues(ki) + ", Kd " + LinkValues(kd)
          : "fractional, " + LinkValues(gain) + " / s^" + LinkValues(order);
  controller += clamp ? FormatText(", clamp +-%g V", v_max) : std::string(", no clamp");
  return {{"controller", controller}, {"actuation", ChoiceText(kActuationNames, scenario.actuation)}};
}

}  // namespace ipmc
