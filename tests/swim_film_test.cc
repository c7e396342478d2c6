// Films of runs, looked at: the decoded video shows the body moving by the
// run's net displacement at the known scale; filming a run as it is done
// and from its output directory give the same frames; recorded states
// round-trip through states.csv; bad video options stop with one line and
// leave no file.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "sim/base/error.h"
#include "renders/swim_film.h"
#include "sim/core/simulation.h"
#include "sim/runs/recorded_states.h"
#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace ipmc::testing {
namespace {

namespace fs = std::filesystem;

std::string ModelPath(const std::string& file) {
  return std::string(IPMC_SWIM_SOURCE_DIR) + "/models/" + file;
}

std::string Quoted(const fs::path& path) { return "'" + path.string() + "'"; }

// Frames `indices` of a video decoded by ffmpeg as width x height RGB.
std::vector<std::vector<unsigned char>> DecodeFrames(const fs::path& video, int width, int height,
                                                     const std::vector<int>& indices) {
  std::string select;
  for (int index : indices) select += (select.empty() ? "" : "+") + ("eq(n\\," + std::to_string(index) + ")");
  const std::string command = "ffmpeg -v error -nostdin -i " + Quoted(video) + " -vf \"select='" +
                              select + "'\" -vsync 0 -f rawvideo -pix_fmt rgb24 -";
  FILE* pipe = popen(command.c_str(), "r");
  std::vector<unsigned char> bytes;
  std::vector<unsigned char> buffer(1 << 16);
  while (size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) {
    bytes.insert(bytes.end(), buffer.begin(), buffer.begin() + n);
  }
  pclose(pipe);
  const size_t frame = static_cast<size_t>(width) * height * 3;
  std::vector<std::vector<unsigned char>> frames;
  for (size_t offset = 0; offset + frame <= bytes.size(); offset += frame) {
    frames.emplace_back(bytes.begin() + offset, bytes.begin() + offset + frame);
  }
  return frames;
}

// The strip's blue (rgba 0.15 0.45 0.8 in the models, drawn at about
// 44, 132, 235): blue clearly above red; the light background, grey grid,
// dark clamp, pale ghost and warm or green trails all fail this.
bool IsBodyColour(const unsigned char* p) { return p[2] > 150 && p[2] > p[0] + 80 && p[1] > p[0]; }
// The clamp (head), drawn dark blue-grey (about 71, 71, 83); the overlay's
// box and the scale bar are neutral grey, the trails coloured.
bool IsClampColour(const unsigned char* p) {
  return p[0] < 100 && p[2] < 110 && p[2] >= p[0] + 6 && std::abs(p[1] - p[0]) < 8;
}
bool IsBackground(const unsigned char* p) { return p[0] > 235 && p[1] > 235 && p[2] > 230; }
bool IsGridGrey(const unsigned char* p) {
  return p[0] > 150 && p[0] < 230 && std::abs(p[0] - p[2]) < 20 && std::abs(p[1] - p[2]) < 20;
}

struct Centroid {
  double column = 0.0, row = 0.0;
  int pixels = 0;
};

template <typename Predicate>
Centroid PixelCentroid(const std::vector<unsigned char>& rgb, int width, int height,
                       Predicate is_part) {
  Centroid c;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      if (!is_part(&rgb[3 * (static_cast<size_t>(y) * width + x)])) continue;
      c.column += x + 0.5;
      c.row += y + 0.5;
      ++c.pixels;
    }
  }
  if (c.pixels > 0) {
    c.column /= c.pixels;
    c.row /= c.pixels;
  }
  return c;
}

// The drawn body's centre of mass in pixels: the links' area centroid
// (a uniform strip) and the clamp's, weighted by mass. The head is the same
// strip, 1 mm of the 31 mm, but drawn thicker, so its share is by length.
Centroid BodyCentroid(const std::vector<unsigned char>& rgb, int width, int height) {
  constexpr double kHeadShare = 1.0 / 31.0;
  const Centroid links = PixelCentroid(rgb, width, height, IsBodyColour);
  const Centroid head = PixelCentroid(rgb, width, height, IsClampColour);
  Centroid body = links;
  if (head.pixels > 0) {
    body.column = (1.0 - kHeadShare) * links.column + kHeadShare * head.column;
    body.row = (1.0 - kHeadShare) * links.row + kHeadShare * head.row;
  }
  return body;
}

// Columns of a CSV file by name.
std::map<std::string, std::vector<double>> ReadCsvColumns(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::istringstream header(line);
  for (std::string cell; std::getline(header, cell, ',');) names.push_back(cell);
  std::map<std::string, std::vector<double>> columns;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::string cell;
    for (size_t k = 0; k < names.size() && std::getline(row, cell, ','); ++k) {
      columns[names[k]].push_back(std::stod(cell));
    }
  }
  return columns;
}

// The value of `column` in the row whose time_s is t (within 1e-9 s).
double AtTime(const std::map<std::string, std::vector<double>>& csv, const std::string& column,
              double t) {
  const std::vector<double>& times = csv.at("time_s");
  for (size_t k = 0; k < times.size(); ++k) {
    if (std::abs(times[k] - t) < 1e-9) return csv.at(column)[k];
  }
  ADD_FAILURE() << "no row at t = " << t;
  return 0.0;
}

// A prescribed travelling wave at 0.2 Hz, 3 cycles (1.5e5 steps): after
// the first cycle's start-up the swimmer covers about 0.4 mm per cycle.
fs::path GaitRun(const fs::path& dir) {
  const fs::path out = dir / "gait";
  const CommandResult result =
      RunCli("gait --model " + Quoted(ModelPath("flagellum3.xml")) +
             " --frequency-hz 0.2 --amplitude-rad 0.6 --cycles 3 --out " + Quoted(out));
  EXPECT_EQ(result.exit_code, 0) << result.output;
  return out;
}

TEST(SwimFilmTest, BodyMovesByTheNetDisplacementAtTheKnownScale) {
  const fs::path dir = FreshDir("film_displacement");
  const fs::path run = GaitRun(dir);
  const fs::path video = dir / "swim.mp4";
  // 1280 px across 40 mm: 32 px/mm. Cycles 2 and 3, 10 frames each: frame
  // 0 at t = 5 s, frame 19 at t = 14.5 s. No trails: where they leave the
  // tips they blend into the strip's end pixels (moving the centroid by up
  // to 1.3 px).
  constexpr int kWidth = 1280, kHeight = 720;
  constexpr double kPxPerMm = kWidth / 40.0;
  const CommandResult result =
      RunCli("render " + Quoted(run) + " --out " + Quoted(video) +
             " --start-cycle 2 --frames-per-cycle 10 --width-px 1280 --height-px 720 --view-mm 40 --trail-frames 0");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("rendering: 20/20 frames (100 %)"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("32 px/mm"), std::string::npos) << result.output;

  const auto frames = DecodeFrames(video, kWidth, kHeight, {0, 19});
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_GT(PixelCentroid(frames[0], kWidth, kHeight, IsClampColour).pixels, 500);
  const Centroid first = BodyCentroid(frames[0], kWidth, kHeight);
  const Centroid last = BodyCentroid(frames[1], kWidth, kHeight);
  // The strip is 0.64 mm wide as drawn and 30 mm long: about 20 000 px.
  ASSERT_GT(first.pixels, 10000);
  ASSERT_GT(last.pixels, 10000);

  const auto csv = ReadCsvColumns(run / "timeseries.csv");
  const double dx_mm = AtTime(csv, "com_x_mm", 14.5) - AtTime(csv, "com_x_mm", 5.0);
  const double dy_mm = AtTime(csv, "com_y_mm", 14.5) - AtTime(csv, "com_y_mm", 5.0);
  const double expected_column = dx_mm * kPxPerMm, expected_row = -dy_mm * kPxPerMm;
  const double moved_column = last.column - first.column, moved_row = last.row - first.row;
  std::printf("centre of mass moved (%.4f, %.4f) mm = (%.2f, %.2f) px; body centroid (%.2f, %.2f) px\n",
              dx_mm, dy_mm, expected_column, expected_row, moved_column, moved_row);
  ASSERT_GT(std::hypot(expected_column, expected_row), 10.0);  // a displacement worth measuring
  // Measured: 0.09 px off in both directions for these two frames; up to
  // 1.2 px for other frames of the film against the first (pixel steps and
  // chroma subsampling at the strip's sides and ends as it turns).
  EXPECT_NEAR(moved_column, expected_column, 1.5);
  EXPECT_NEAR(moved_row, expected_row, 1.5);
}

// The last of 5 frames of cycle 3 of a gait run filmed at the default size
// (1280 x 720); empty if the film could not be made.
std::vector<unsigned char> LastFrameOfCycle3(const std::string& name) {
  const fs::path dir = FreshDir(name);
  const fs::path run = GaitRun(dir);
  const fs::path video = dir / "swim.mp4";
  if (RunCli("render " + Quoted(run) + " --out " + Quoted(video) +
             " --start-cycle 3 --frames-per-cycle 5")
          .exit_code != 0) {
    return {};
  }
  const FilmConfig defaults;
  const auto frames = DecodeFrames(video, defaults.width, defaults.height, {4});
  return frames.size() == 1 ? frames[0] : std::vector<unsigned char>{};
}

TEST(SwimFilmTest, FrameIsNotBlank) {
  const FilmConfig defaults;  // 1280 x 720
  const std::vector<unsigned char> rgb = LastFrameOfCycle3("film_frame");
  ASSERT_EQ(rgb.size(), 3u * defaults.width * defaults.height);
  int body = 0, background = 0, grid = 0;
  for (size_t i = 0; i < rgb.size(); i += 3) {
    body += IsBodyColour(&rgb[i]);
    background += IsBackground(&rgb[i]);
    grid += IsGridGrey(&rgb[i]);
  }
  std::printf("body %d, background %d, grid %d of %d px\n", body, background, grid,
              defaults.width * defaults.height);
  // Measured at 1280 x 720: 24 600 body, 753 000 background, 122 000 grid
  // pixels (and the overlay's panels, the trails, the clamp).
  EXPECT_GT(body, 2000);
  EXPECT_GT(background, 100000);
  EXPECT_GT(grid, 20000);
}

// WCAG 2's relative luminance of an sRGB pixel and the contrast ratio of
// two luminances, (L1 + 0.05) / (L2 + 0.05), L1 the lighter.
double Luminance(const unsigned char* p) {
  double channel[3];
  for (int k = 0; k < 3; ++k) {
    const double c = p[k] / 255.0;
    channel[k] = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  }
  return 0.2126 * channel[0] + 0.7152 * channel[1] + 0.0722 * channel[2];
}

double ContrastRatio(double a, double b) {
  return (std::max(a, b) + 0.05) / (std::min(a, b) + 0.05);
}

TEST(SwimFilmTest, OverlayTextStandsOutFromItsPanel) {
  const FilmConfig defaults;
  const std::vector<unsigned char> frame = LastFrameOfCycle3("film_legible");
  ASSERT_EQ(frame.size(), 3u * defaults.width * defaults.height);
  // The table's panel covers the top left corner, the legend's the bottom
  // left: in each, the panel is the lightest pixel and the text the darkest.
  const auto corner = [&](int row0, int rows) {
    double lightest = 0.0, darkest = 1.0;
    for (int y = row0; y < row0 + rows; ++y) {
      for (int x = 0; x < 180; ++x) {
        const double l = Luminance(&frame[3 * (static_cast<size_t>(y) * defaults.width + x)]);
        lightest = std::max(lightest, l);
        darkest = std::min(darkest, l);
      }
    }
    return ContrastRatio(lightest, darkest);
  };
  const double table = corner(0, 100), legend = corner(defaults.height - 40, 40);
  std::printf("contrast ratio: table %.1f, legend %.1f\n", table, legend);
  // WCAG 2 asks 7 for enhanced contrast; the panel and text colours give
  // 16.3 (values) and 7.4 (labels) before encoding
  // (renders/offscreen_renderer.cc). Measured on the decoded frame: 10.9
  // over the table's corner, 20.5 over the legend's.
  EXPECT_GT(table, 7.0);
  EXPECT_GT(legend, 7.0);
}

// One cycle of 2 s at a 0.5 ms step.
fs::path ShortScenario(const fs::path& dir) {
  const fs::path path = dir / "short.toml";
  std::ofstream(path) << "model = \"" << ModelPath("flagellum3.xml") << "\"\n"
                      << "cycles = 1\ntimestep_s = 5e-4\n"
                      << "[waveform]\nfrequency_Hz = 0.5\n";
  return path;
}

TEST(SwimFilmTest, FilmingTheRunAndItsOutputsGiveTheSameFrames) {
  const fs::path dir = FreshDir("film_same");
  const fs::path out = dir / "run";
  const CommandResult run = RunCli("run " + Quoted(ShortScenario(dir)) + " --out " + Quoted(out) +
                                   " --video " + Quoted(dir / "during.mp4") +
                                   " --frames-per-cycle 10");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  // The results come first, then the film.
  EXPECT_LT(run.output.find("mean speed"), run.output.find("written to"));
  ASSERT_EQ(RunCli("render " + Quoted(out) + " --out " + Quoted(dir / "after.mp4") +
                   " --frames-per-cycle 10")
                .exit_code,
            0);
  const std::vector<int> all = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  const FilmConfig defaults;
  const auto during = DecodeFrames(dir / "during.mp4", defaults.width, defaults.height, all);
  const auto after = DecodeFrames(dir / "after.mp4", defaults.width, defaults.height, all);
  ASSERT_EQ(during.size(), 10u);
  ASSERT_EQ(after.size(), 10u);
  for (size_t k = 0; k < during.size(); ++k) EXPECT_TRUE(during[k] == after[k]) << "frame " << k;
  EXPECT_FALSE(during[0] == during[5]);  // the body moves
}

// The film's checks name its fields, not flags: the command line puts its
// flag in place (above), Python would keep the name.
TEST(SwimFilmTest, ValidateNamesTheField) {
  FilmConfig film;
  film.width = 641;
  try {
    film.Validate();
    ADD_FAILURE() << "an odd width passed";
  } catch (const FieldError& error) {
    EXPECT_EQ(error.field(), "width_px");
    EXPECT_STREQ(error.what(), "video: width_px must be positive and even (got 641)");
  }
  film = FilmConfig{};
  film.camera = FilmCamera::kFollow;
  film.center_mm = {1.0, 2.0};
  try {
    film.Validate();
    ADD_FAILURE() << "a centre for the follow camera passed";
  } catch (const FieldError& error) {
    EXPECT_EQ(error.field(), "center_mm");
  }
}

TEST(SwimFilmTest, BadVideoOptionsStopWithOneLineAndNoFile) {
  const fs::path dir = FreshDir("film_bad");
  const fs::path run = dir / "run";
  ASSERT_EQ(RunCli("run " + Quoted(ShortScenario(dir)) + " --out " + Quoted(run)).exit_code, 0);
  const fs::path video = dir / "bad.mp4";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--elevation-deg 10", "--elevation-deg"},
      {"--view-mm -5", "--view-mm"},
      {"--strip-thickness-mm 20", "--strip-thickness-mm"},
      {"--camera follow --center-mm 1,2", "--center-mm"},
      {"--camera sideways", "--camera"},
      {"--width-px 2000", "offwidth"},
      {"--start-cycle 2", "--start-cycle"},
      {"--cycles 3", "--cycles"},
  };
  for (const auto& [options, named] : cases) {
    const CommandResult result =
        RunCli("render " + Quoted(run) + " --out " + Quoted(video) + " " + options);
    EXPECT_NE(result.exit_code, 0) << options;
    EXPECT_NE(result.output.find(named), std::string::npos) << options << ": " << result.output;
    EXPECT_EQ(CountLines(result.output), 1) << options << ": " << result.output;
  }
  const CommandResult no_video = RunCli("run " + Quoted(ShortScenario(dir)) + " --camera follow");
  EXPECT_NE(no_video.exit_code, 0);
  EXPECT_NE(no_video.output.find("--video"), std::string::npos) << no_video.output;
  const CommandResult no_states = RunCli("render " + Quoted(dir) + " --out " + Quoted(video));
  EXPECT_NE(no_states.exit_code, 0);
  EXPECT_NE(no_states.output.find("summary.json"), std::string::npos) << no_states.output;
  // Nothing but the scenario and the run's outputs.
  for (const auto& entry : fs::directory_iterator(dir)) {
    EXPECT_TRUE(entry.path().filename() == "short.toml" || entry.path().filename() == "run")
        << entry.path();
  }
}

TEST(RecordedStatesTest, RoundTripThroughCsvAndInterpolate) {
  const ModelPtr model = LoadModelFile(ModelPath("flagellum3.xml"));
  const mjModel* m = model.get();
  DataPtr data(mj_makeData(m));
  RecordedStates states = RecordedStates::For(m);
  EXPECT_EQ(states.columns,
            (std::vector<std::string>{"root_x_m", "root_y_m", "root_yaw_rad", "j1_rad", "j2_rad", "j3_rad"}));
  for (int k = 0; k < 3; ++k) {
    data->time = 0.5 * k;
    for (int i = 0; i < m->nq; ++i) data->qpos[i] = std::sin(1.0 + k + 0.3 * i) / 3.0;
    states.Record(data.get());
  }
  const fs::path path = FreshDir("states") / "states.csv";
  std::ofstream(path) << RecordedStatesCsv(states);
  const RecordedStates read = ReadRecordedStates(path.string(), m);
  EXPECT_EQ(read.t_s, states.t_s);
  EXPECT_EQ(read.qpos, states.qpos);  // 17 significant digits: exact
  EXPECT_EQ(read.StateAt(m, 0.5), states.qpos[1]);
  const std::vector<double> between = read.StateAt(m, 0.625);
  for (int i = 0; i < m->nq; ++i) {
    EXPECT_DOUBLE_EQ(between[i], 0.75 * states.qpos[1][i] + 0.25 * states.qpos[2][i]);
  }
  EXPECT_EQ(read.StateAt(m, 7.0), states.qpos[2]);  // clamped to the recorded span

  // A model without hinge j3 cannot replay these states... and a file
  // without j3's column names it.
  std::string csv = RecordedStatesCsv(states);
  csv.replace(csv.find("j3_rad"), 6, "jX_rad");
  std::ofstream(path) << csv;
  ExpectThrowMentioning<std::runtime_error>([&] { ReadRecordedStates(path.string(), m); },
                                            "no column j3_rad");
}

TEST(SwimFilmConfigTest, NamesTheFieldOutOfRange) {
  const auto expect_bad = [](const std::string& field, auto change) {
    FilmConfig config;
    change(config);
    ExpectInvalidArgument([&] { config.Validate(); }, field);
  };
  FilmConfig().Validate();
  expect_bad("width_px", [](FilmConfig& c) { c.width = 641; });
  expect_bad("fps", [](FilmConfig& c) { c.fps = 0.0; });
  expect_bad("frames_per_cycle", [](FilmConfig& c) { c.frames_per_cycle = 0; });
  expect_bad("view_mm", [](FilmConfig& c) { c.view_mm = 2e4; });
  expect_bad("center_mm", [](FilmConfig& c) { c.center_mm = {1.0}; });
  expect_bad("elevation_deg", [](FilmConfig& c) { c.elevation_deg = -95.0; });
  expect_bad("azimuth_deg", [](FilmConfig& c) { c.azimuth_deg = 400.0; });
  expect_bad("strip_thickness_mm", [](FilmConfig& c) { c.strip_thickness_mm = -1.0; });
}

}  // namespace
}  // namespace ipmc::testing
