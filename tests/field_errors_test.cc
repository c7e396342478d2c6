// Bad values of the bench signal (sim/runs/bench_run.h), the model
// generator's spec (sim/core/model_generator.h), the renderer
// (renders/offscreen_renderer.h), the video writer (renders/video.h) and
// the film (renders/swim_film.h) are FieldErrors that name the field, the
// part that callers decide by and the command line puts its flag in place
// of; a run's output directory that is not one is an InputError naming
// the missing file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "sim/base/error.h"
#include "renders/offscreen_renderer.h"
#include "renders/swim_film.h"
#include "renders/video.h"
#include "sim/core/data_paths.h"
#include "sim/core/model_generator.h"
#include "sim/core/simulation.h"
#include "sim/runs/bench_run.h"
#include "tests/cli_util.h"

namespace ipmc::testing {
namespace {

// The field of the FieldError that `statement` throws; "none" if it
// throws none.
std::string FieldOf(const std::function<void()>& statement) {
  try {
    statement();
  } catch (const FieldError& error) {
    EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos) << error.what();
    return error.field();
  }
  return "none";
}

struct Case {
  std::string what;
  std::function<void()> statement;
  std::string field;
};

void ExpectFields(const std::vector<Case>& cases) {
  for (const Case& c : cases) EXPECT_EQ(FieldOf(c.statement), c.field) << c.what;
}

BenchSignal Signal(const std::function<void(BenchSignal&)>& change) {
  BenchSignal signal;
  change(signal);
  return signal;
}

TEST(FieldErrorsTest, BenchSignalNamesItsField) {
  const auto validate = [](const std::function<void(BenchSignal&)>& change) {
    return [=] { Signal(change).Validate(); };
  };
  ExpectFields({
      {"amplitude", validate([](BenchSignal& s) { s.amplitude_V = 1e9; }), "amplitude_V"},
      {"amplitude nan", validate([](BenchSignal& s) { s.amplitude_V = std::nan(""); }),
       "amplitude_V"},
      {"duration", validate([](BenchSignal& s) { s.duration_s = 0; }), "duration_s"},
      {"sample rate", validate([](BenchSignal& s) { s.sample_rate_Hz = -1; }), "sample_rate_Hz"},
      {"frequency", validate([](BenchSignal& s) { s.frequency_Hz = 0; }), "frequency_Hz"},
      {"start", validate([](BenchSignal& s) { s.kind = BenchSignal::Kind::kChirp; s.start_Hz = 0; }),
       "start_Hz"},
      {"end", validate([](BenchSignal& s) { s.kind = BenchSignal::Kind::kChirp; s.end_Hz = 0.05; }),
       "end_Hz"},
      {"links", validate([](BenchSignal& s) { s.driven_links.clear(); }), "driven_links"},
      {"the default", validate([](BenchSignal&) {}), "none"},
  });
  Simulation sim(LoadModelFile(ModelsDir() + "/flagellum3_clamped.xml"), "clamped.xml");
  const auto run = [&](const std::function<void(BenchSignal&)>& change) {
    return [&, change] { RunBench(sim, Signal([&](BenchSignal& s) { s.duration_s = 0.01; change(s); })); };
  };
  ExpectFields({
      {"link 4", run([](BenchSignal& s) { s.driven_links = {4}; }), "driven_links"},
      {"uneven sampling", run([](BenchSignal& s) { s.sample_rate_Hz = 333; }), "sample_rate_Hz"},
      {"too long", run([](BenchSignal& s) { s.duration_s = 1e300; }), "duration_s"},
      {"beyond the limits", run([](BenchSignal& s) { s.duration_s = 1e5; }), "duration_s"},
  });
}

TEST(FieldErrorsTest, FlagellumSpecNamesItsField) {
  const auto validate = [](const std::function<void(FlagellumSpec&)>& change) {
    return [=] {
      FlagellumSpec spec;
      change(spec);
      spec.Validate();
    };
  };
  ExpectFields({
      {"no links", validate([](FlagellumSpec& s) { s.link_lengths_mm.clear(); }), "link_lengths_mm"},
      {"negative link", validate([](FlagellumSpec& s) { s.link_lengths_mm = {10, -1}; }),
       "link_lengths_mm"},
      {"too many links", validate([](FlagellumSpec& s) { s.link_lengths_mm.assign(65, 1.0); }),
       "link_lengths_mm"},
      {"name", validate([](FlagellumSpec& s) { s.name = "a<b"; }), "name"},
      {"gap", validate([](FlagellumSpec& s) { s.gap_mm = -1; }), "gap_mm"},
      {"width", validate([](FlagellumSpec& s) { s.width_mm = 0; }), "width_mm"},
      {"timestep", validate([](FlagellumSpec& s) { s.timestep_s = 0; }), "timestep_s"},
      {"integrator", validate([](FlagellumSpec& s) { s.integrator = "leapfrog"; }), "integrator"},
      {"viscosity", validate([](FlagellumSpec& s) { s.viscosity_Pa_s = -1; }), "viscosity_Pa_s"},
      {"coefficients", validate([](FlagellumSpec& s) { s.coefficients = "stokes"; }),
       "coefficients"},
      {"xi", validate([](FlagellumSpec& s) { s.coefficients = "direct"; }), "xi_normal_N_s_m2"},
      {"segments", validate([](FlagellumSpec& s) { s.segments_per_link = 0; }), "segments_per_link"},
      {"nesting", validate([](FlagellumSpec& s) { s.segments_per_link = 32; }), "segments_per_link"},
      {"plants", validate([](FlagellumSpec& s) { s.plants = "per_link"; }), "plants"},
      {"ipmc model", validate([](FlagellumSpec& s) { s.ipmc_model = "g3"; }), "ipmc_model"},
      {"actuation", validate([](FlagellumSpec& s) { s.actuation = "all"; }), "actuation"},
      {"wavelength", validate([](FlagellumSpec& s) { s.wavelength_mm = 0.5; }), "wavelength_mm"},
      {"the default", validate([](FlagellumSpec&) {}), "none"},
  });
}

TEST(FieldErrorsTest, RendererVideoAndFilmNameTheirFields) {
  const ModelPtr model = LoadModelFile(ModelsDir() + "/flagellum3.xml");
  const mjModel* m = model.get();
  const auto camera = [](const std::function<void(CameraSetup&)>& change) {
    return [=] {
      CameraSetup setup;
      change(setup);
      OffscreenRenderer::ValidateCamera(setup);
    };
  };
  RendererOptions long_trail;
  long_trail.trail_length = -1;
  RendererOptions thick;
  thick.strip_thickness_m = 1.0;
  const std::string png = (std::filesystem::temp_directory_path() / "f.png").string();
  const std::string mp4 = (std::filesystem::temp_directory_path() / "f.mp4").string();
  const RecordedStates none;
  ExpectFields({
      {"body fill", camera([](CameraSetup& c) { c.body_fill = 0; }), "body_fill"},
      {"view", camera([](CameraSetup& c) { c.view_width_m = -1; }), "view_width_m"},
      {"elevation", camera([](CameraSetup& c) { c.elevation_deg = 0; }), "elevation_deg"},
      {"azimuth", camera([](CameraSetup& c) { c.azimuth_deg = 400; }), "azimuth_deg"},
      {"look-at", camera([](CameraSetup& c) { c.lookat_m[1] = std::nan(""); }), "lookat_m"},
      {"width 0", [&] { OffscreenRenderer::CheckImageSize(m, 0, 480); }, "width"},
      {"height 0", [&] { OffscreenRenderer::CheckImageSize(m, 640, -2); }, "height"},
      {"too wide", [&] { OffscreenRenderer::CheckImageSize(m, 100000, 480); }, "width"},
      {"no model", [&] { OffscreenRenderer(nullptr, 640, 480); }, "model"},
      {"trail", [&] { OffscreenRenderer(m, 640, 480, long_trail); }, "trail_length"},
      {"strip", [&] { OffscreenRenderer(m, 640, 480, thick); }, "strip_thickness_m"},
      {"png size", [&] { WritePng(png, {}, 0, 4); }, "width"},
      {"png bytes", [&] { WritePng(png, std::vector<unsigned char>(5), 2, 2); }, "rgb"},
      {"odd video", [&] { Mp4Writer(mp4, 641, 480, 25.0); }, "width"},
      {"video fps", [&] { Mp4Writer(mp4, 640, 480, 0.0); }, "fps"},
      {"no states", [&] { FilmRun({m, &none, 1.0, 1, {}, {}}, FilmConfig{}, mp4); }, "states"},
      {"film too wide",
       [&] {
         FilmConfig config;
         config.height = 100000;
         CheckFilmFits(m, config);
       },
       "height_px"},
  });
  EXPECT_FALSE(std::filesystem::exists(png));
  EXPECT_FALSE(std::filesystem::exists(mp4));
}

TEST(FieldErrorsTest, AFolderThatIsNoRunsOutputIsAnInputErrorNamingTheFile) {
  const std::filesystem::path dir = FreshDir("not_a_run");
  try {
    LoadRunRecording(dir.string());
    ADD_FAILURE() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(error.problem(), InputProblem::kMissing);
    EXPECT_EQ(error.key(), "summary.json");
    EXPECT_EQ(error.where().file, dir.string());
    EXPECT_NE(std::string(error.what()).find("not a run's output directory"), std::string::npos);
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ipmc::testing
