// Off-screen rendering: frames of the free and clamped flagellum show the
// body where the camera's projection puts it; PNG and MP4 files decode to
// what was written; `render` films a short scenario.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include "renders/offscreen_renderer.h"
#include "renders/swim_film.h"
#include "sim/cli/render_command.h"
#include "renders/video.h"
#include "sim/core/simulation.h"
#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace ipmc::testing {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 640;
constexpr int kHeight = 480;

fs::path RenderDir(const std::string& name) { return FreshDir("render_" + name); }

std::string ModelPath(const std::string& file) {
  return std::string(IPMC_SWIM_SOURCE_DIR) + "/models/" + file;
}

// The links' colour (rgba 0.15 0.45 0.8) under the renderer's lights: blue
// clearly above red, unlike the black background, the grey head and sites,
// the white overlay text and the warm trails.
bool IsBodyColour(const unsigned char* p) { return p[2] > 150 && p[2] > p[0] + 80 && p[1] > p[0]; }

// Pixel (column, row from the top) where the scene's OpenGL camera projects
// the world point p: the frustum of mjr_render, glFrustum(center -+ w,
// bottom, top, near) with half-width w = aspect (top - bottom) / 2, looking
// along `forward` with `up` up and forward x up to the right.
std::array<double, 2> ProjectToPixel(const mjvScene& scn, const mjtNum p[3], int width, int height) {
  const mjvGLCamera cam = mjv_averageCamera(&scn.camera[0], &scn.camera[1]);
  float right[3];
  right[0] = cam.forward[1] * cam.up[2] - cam.forward[2] * cam.up[1];
  right[1] = cam.forward[2] * cam.up[0] - cam.forward[0] * cam.up[2];
  right[2] = cam.forward[0] * cam.up[1] - cam.forward[1] * cam.up[0];
  double x = 0, y = 0, z = 0;
  for (int i = 0; i < 3; ++i) {
    const double rel = p[i] - cam.pos[i];
    x += rel * right[i];
    y += rel * cam.up[i];
    z += rel * cam.forward[i];
  }
  const double near_x = cam.frustum_near * x / z;
  const double near_y = cam.frustum_near * y / z;
  const double half_width =
      0.5 * width / height * (cam.frustum_top - cam.frustum_bottom);
  const double left = cam.frustum_center - half_width;
  return {(near_x - left) / (2.0 * half_width) * width,
          (cam.frustum_top - near_y) / (cam.frustum_top - cam.frustum_bottom) * height};
}

struct PixelStats {
  double variance = 0.0;
  int body_pixels = 0;
};

PixelStats Stats(const std::vector<unsigned char>& rgb) {
  PixelStats stats;
  double sum = 0.0, sum2 = 0.0;
  for (unsigned char v : rgb) {
    sum += v;
    sum2 += static_cast<double>(v) * v;
  }
  const double n = static_cast<double>(rgb.size());
  stats.variance = sum2 / n - (sum / n) * (sum / n);
  for (size_t i = 0; i < rgb.size(); i += 3) stats.body_pixels += IsBodyColour(&rgb[i]);
  return stats;
}

// Distance from (column, row) to the nearest body-coloured pixel.
double DistanceToBody(const std::vector<unsigned char>& rgb, double column, double row) {
  double best = 1e9;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      if (!IsBodyColour(&rgb[3 * (static_cast<size_t>(y) * kWidth + x)])) continue;
      best = std::min(best, std::hypot(x + 0.5 - column, y + 0.5 - row));
    }
  }
  return best;
}

// The model bent into a zigzag, so that a mirrored image would put the
// tail elsewhere.
struct BentModel {
  ModelPtr model;
  mjData* data;
  explicit BentModel(const std::string& file) : model(LoadModelFile(ModelPath(file))) {
    data = mj_makeData(model.get());
    const char* joints[] = {"j1", "j2", "j3"};
    const double angles_rad[] = {0.3, -0.3, 0.4};
    for (int j = 0; j < 3; ++j) {
      const int id = mj_name2id(model.get(), mjOBJ_JOINT, joints[j]);
      data->qpos[model->jnt_qposadr[id]] = angles_rad[j];
    }
    mj_forward(model.get(), data);
  }
  ~BentModel() { mj_deleteData(data); }
};

void ExpectBodyWhereProjected(const std::string& file) {
  SCOPED_TRACE(file);
  BentModel bent(file);
  OffscreenRenderer renderer(bent.model.get(), kWidth, kHeight);
  const std::vector<unsigned char> rgb = renderer.Frame(bent.data);
  ASSERT_EQ(rgb.size(), static_cast<size_t>(kWidth) * kHeight * 3);
  const PixelStats stats = Stats(rgb);
  // Measured: variance 295 and 1017 body pixels (both models).
  EXPECT_GT(stats.variance, 50.0);
  EXPECT_GT(stats.body_pixels, 500);

  // The tail is up and to the right of the image centre (tip3 is at
  // y = +4.3 mm here); a mirrored or shifted image puts it elsewhere.
  const int tip3 = mj_name2id(bent.model.get(), mjOBJ_SITE, "tip3");
  const std::array<double, 2> tail =
      ProjectToPixel(renderer.scene(), bent.data->site_xpos + 3 * tip3, kWidth, kHeight);
  EXPECT_GT(tail[0], 0.7 * kWidth);
  EXPECT_LT(tail[1], 0.45 * kHeight);
  // Every link tip has a body pixel next to its projection (the sites'
  // spheres lie inside the strip, under its top face). Measured: 0.3 to
  // 0.9 px.
  for (const char* site : {"tip1", "tip2", "tip3"}) {
    const int id = mj_name2id(bent.model.get(), mjOBJ_SITE, site);
    const std::array<double, 2> pixel =
        ProjectToPixel(renderer.scene(), bent.data->site_xpos + 3 * id, kWidth, kHeight);
    const double distance = DistanceToBody(rgb, pixel[0], pixel[1]);
    std::printf("%s: %s at (%.1f, %.1f) px, nearest body pixel %.2f px away\n", file.c_str(), site,
                pixel[0], pixel[1], distance);
    EXPECT_LT(distance, 3.0) << site;
  }
}

TEST(OffscreenRendererTest, FreeSwimmerIsDrawnWhereTheCameraProjectsIt) {
  ExpectBodyWhereProjected("flagellum3.xml");
}

TEST(OffscreenRendererTest, ClampedModelIsDrawnWhereTheCameraProjectsIt) {
  ExpectBodyWhereProjected("flagellum3_clamped.xml");
}

TEST(OffscreenRendererTest, RefusesImagesLargerThanTheOffscreenBuffer) {
  const ModelPtr model = LoadModelFile(ModelPath("flagellum3.xml"));
  ExpectThrowMentioning<std::invalid_argument>(
      [&] { OffscreenRenderer renderer(model.get(), 1920, 1080); }, "1280x720");
}

// A frame of colour bars that move with the frame index.
std::vector<unsigned char> TestPattern(int width, int height, int index) {
  std::vector<unsigned char> rgb(static_cast<size_t>(width) * height * 3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      unsigned char* p = &rgb[3 * (static_cast<size_t>(y) * width + x)];
      p[0] = static_cast<unsigned char>((x + 8 * index) % 256);
      p[1] = static_cast<unsigned char>(y % 256);
      p[2] = static_cast<unsigned char>(((x / 32 + y / 32) % 2) * 200);
    }
  }
  return rgb;
}

// What ffprobe reports of the first video stream: nb_read_frames (decoded
// frames), width and height.
std::map<std::string, int> Probe(const fs::path& video) {
  const std::string command =
      "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
      "stream=nb_read_frames,width,height -of default=noprint_wrappers=1 '" +
      video.string() + "' 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  char buffer[1024];
  while (size_t n = std::fread(buffer, 1, sizeof(buffer), pipe)) output.append(buffer, n);
  pclose(pipe);
  std::map<std::string, int> values;
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);) {
    const size_t eq = line.find('=');
    if (eq != std::string::npos) values[line.substr(0, eq)] = std::atoi(line.c_str() + eq + 1);
  }
  return values;
}

TEST(VideoTest, TwentyFrameMp4DecodesToTwentyFrames) {
  const fs::path dir = RenderDir("mp4");
  const fs::path out = dir / "pattern.mp4";
  Mp4Writer video(out.string(), 320, 240, 25.0);
  for (int k = 0; k < 20; ++k) video.AddFrame(TestPattern(320, 240, k));
  video.Finish();
  EXPECT_FALSE(fs::exists(out.string() + ".tmp.mp4"));
  std::map<std::string, int> probe = Probe(out);
  EXPECT_EQ(probe["nb_read_frames"], 20);
  EXPECT_EQ(probe["width"], 320);
  EXPECT_EQ(probe["height"], 240);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(VideoTest, UnfinishedOrFailedVideoLeavesNoFile) {
  const fs::path dir = RenderDir("mp4_failed");
  {
    Mp4Writer video((dir / "unfinished.mp4").string(), 64, 48, 10.0);
    video.AddFrame(TestPattern(64, 48, 0));
  }
  // ffmpeg cannot write its output where a directory stands.
  const fs::path blocked = dir / "blocked.mp4";
  fs::create_directory(blocked.string() + ".tmp.mp4");
  try {
    Mp4Writer video(blocked.string(), 64, 48, 10.0);
    for (int k = 0; k < 3; ++k) video.AddFrame(TestPattern(64, 48, k));
    video.Finish();
    ADD_FAILURE() << "expected ffmpeg to fail";
  } catch (const std::runtime_error& error) {
    std::printf("%s\n", error.what());
    EXPECT_NE(std::string(error.what()).find("blocked.mp4"), std::string::npos) << error.what();
  }
  fs::remove(blocked.string() + ".tmp.mp4");
  EXPECT_TRUE(fs::is_empty(dir));
  ExpectThrowMentioning<std::invalid_argument>(
      [&] { Mp4Writer odd((dir / "odd.mp4").string(), 65, 48, 10.0); }, "65x48");
}

TEST(VideoTest, PngDecodesToTheSamePixels) {
  const fs::path path = RenderDir("png") / "pattern.png";
  const std::vector<unsigned char> rgb = TestPattern(96, 64, 3);
  WritePng(path.string(), rgb, 96, 64);
  int width = 0, height = 0, channels = 0;
  unsigned char* decoded = stbi_load(path.c_str(), &width, &height, &channels, 3);
  ASSERT_NE(decoded, nullptr);
  EXPECT_EQ(width, 96);
  EXPECT_EQ(height, 64);
  EXPECT_EQ(std::vector<unsigned char>(decoded, decoded + rgb.size()), rgb);
  stbi_image_free(decoded);
}

// One 2 s wave period at a 0.5 ms step (4000 steps), filmed at 10 frames.
fs::path ShortScenario(const fs::path& dir) {
  const fs::path path = dir / "short.toml";
  std::ofstream(path) << "model = \"" << ModelPath("flagellum3.xml") << "\"\n"
                      << "cycles = 1\ntimestep_s = 5e-4\n"
                      << "[waveform]\nfrequency_Hz = 0.5\n"
                      << "[output]\ndir = \"" << (dir / "scenario_out").string() << "\"\n";
  return path;
}

int RunRenderInProcess(std::vector<std::string> args) {
  CLI::App app{"render test"};
  RenderArgs render;
  AddRenderCommand(app, render);
  args.insert(args.begin(), "render");
  std::reverse(args.begin(), args.end());  // CLI11 parses a vector from the back
  app.parse(args);
  return RunRenderCommandLine(app, render);
}

// The overlay names the gains that ran: the scalar keys', or each link's
// where controller.link_* gives them (in link order).
TEST(OverlayTest, ShowsTheGainsThatRan) {
  ipmc::ScenarioConfig scenario;
  EXPECT_EQ(ipmc::ClosedLoopOverlayRows(scenario)[0][1],
            "PID, Kp 8.12, Ki 53.36, Kd 0.61, clamp +-6 V");
  scenario.controller.link_gains.kp = {10.3, 2.6, 1.2};
  scenario.controller.link_gains.ki = {36, 9, 4};
  EXPECT_EQ(ipmc::ClosedLoopOverlayRows(scenario)[0][1],
            "PID, Kp 10.3/2.6/1.2, Ki 36/9/4, Kd 0.61, clamp +-6 V");
  scenario.controller.kind = ipmc::ControllerKind::kFractional;
  scenario.controller.fractional.clamp_enabled = false;
  scenario.controller.link_gains.gain = {14.6, 3.7, 1.6};
  EXPECT_EQ(ipmc::ClosedLoopOverlayRows(scenario)[0][1], "fractional, 14.6/3.7/1.6 / s^0.62, no clamp");
  scenario.actuation = ipmc::Actuation::kSingle;
  EXPECT_EQ(ipmc::ClosedLoopOverlayRows(scenario)[0][1], "fractional, 14.6 / s^0.62, no clamp");
}

TEST(RenderCommandTest, FilmsAShortScenario) {
  const fs::path dir = RenderDir("command");
  const fs::path scenario = ShortScenario(dir);
  const fs::path out = dir / "films" / "short.mp4";
  ASSERT_EQ(RunRenderInProcess({scenario.string(), "--out", out.string(), "--frames-per-cycle",
                                "10", "--png-dir", (dir / "png").string()}),
            0);
  std::map<std::string, int> probe = Probe(out);
  EXPECT_EQ(probe["nb_read_frames"], 10);
  const FilmConfig defaults;  // the film's size unless --width-px/--height-px say otherwise
  EXPECT_EQ(probe["width"], defaults.width);
  EXPECT_EQ(probe["height"], defaults.height);
  EXPECT_TRUE(fs::exists(dir / "png" / "frame_00009.png"));
  EXPECT_FALSE(fs::exists(dir / "png" / "frame_00010.png"));
  EXPECT_FALSE(fs::exists(dir / "scenario_out"));  // the scenario's outputs are not written
}

TEST(RenderCommandTest, BadOptionsWriteNothing) {
  const fs::path dir = RenderDir("command_bad");
  const fs::path scenario = ShortScenario(dir);
  const fs::path out = dir / "bad.mp4";
  ExpectInvalidArgument(
      [&] { RunRenderInProcess({scenario.string(), "--out", out.string(), "--width-px", "641"}); },
      "--width-px");
  ExpectInvalidArgument(
      [&] { RunRenderInProcess({scenario.string(), "--out", out.string(), "--start-cycle", "2"}); },
      "--start-cycle");
  // Larger than the model's 1280x720 offscreen buffer: refused at t = 0.
  ExpectInvalidArgument(
      [&] {
        RunRenderInProcess({scenario.string(), "--out", out.string(), "--width-px", "1920", "--height-px",
                            "1080", "--png-dir", (dir / "png").string()});
      },
      "offwidth");
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(fs::is_empty(dir / "png"));
  CLI::App app{"render test"};
  RenderArgs render;
  AddRenderCommand(app, render);
  EXPECT_EQ(RunRenderCommandLine(app, render), -1);  // nothing parsed: not chosen
}

// The same through the ipmc-swim program, which lists "render" among its
// commands: a program without it fails here.
TEST(RenderCommandTest, ProgramFilmsAShortScenario) {
  EXPECT_NE(RunCli("--help").output.find("\n  render"), std::string::npos)
      << "ipmc-swim --help lists no render command";
  const fs::path dir = RenderDir("program");
  const fs::path out = dir / "short.mp4";
  const CommandResult result = RunCli("render '" + ShortScenario(dir).string() + "' --out '" +
                                      out.string() + "' --frames-per-cycle 5");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(Probe(out)["nb_read_frames"], 5);
}

}  // namespace
}  // namespace ipmc::testing
