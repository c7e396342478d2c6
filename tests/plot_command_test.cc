// The plot subcommand: every figure kind draws from the program's own
// outputs (bode.csv, step.csv, closed-loop and gait timeseries.csv, an
// identification's response.csv, a sweep table), generated here by running
// ipmc-swim, into the format of --out's extension; titles name what is
// shown and no path, axes are labelled from the table of column labels,
// the Bode margins agree with the bode command's; a missing column, an
// unknown extension, an option of another kind or a failing gnuplot gives
// one line and no file.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "renders/figure_parts.h"
#include "renders/figures.h"
#include "sim/io/csv.h"
#include "tests/cli_util.h"

namespace {

namespace fs = std::filesystem;
using ipmc::testing::CommandResult;
using ipmc::testing::CountLines;
using ipmc::testing::RunCli;

// A blank 1000 x 700 pngcairo image is 3.7 kB; the figures here, with
// axes, labels and curves, are 25 kB and more. 10 kB tells a drawn figure
// from a blank or truncated one.
constexpr std::uintmax_t kMinFigureBytes = 10 * 1024;
constexpr char kPngSignature[] = "\x89PNG\r\n\x1a\n";
constexpr char kPngEnd[] = "IEND\xae\x42\x60\x82";  // the last chunk and its CRC

fs::path FreshDir(const std::string& name) { return ipmc::testing::FreshDir("plot_" + name); }

std::string Quoted(const fs::path& path) { return "'" + path.string() + "'"; }

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// The paper's scenario, shortened: `cycles` cycles of a `frequency_Hz`
// wave with `actuation`, model path made absolute. Fails the test if the
// file no longer has one of the keys.
fs::path ShortScenario(const fs::path& dir, const std::string& name, double frequency_Hz,
                       int cycles, const std::string& actuation) {
  std::istringstream paper(ReadText(fs::path(IPMC_SWIM_SOURCE_DIR) / "scenarios" / "paper.toml"));
  const std::vector<std::pair<std::string, std::string>> replacements = {
      {"model =", "model = \"" + std::string(IPMC_SWIM_SOURCE_DIR) + "/models/flagellum3.xml\""},
      {"actuation =", "actuation = \"" + actuation + "\""},
      {"cycles =", "cycles = " + std::to_string(cycles)},
      {"timestep_s =", "timestep_s = 5e-4"},
      {"frequency_Hz =", "frequency_Hz = " + std::to_string(frequency_Hz)}};
  std::string text;
  int replaced = 0;
  for (std::string line; std::getline(paper, line);) {
    for (const auto& [key, value] : replacements) {
      if (line.rfind(key, 0) == 0) {
        line = value;
        ++replaced;
      }
    }
    text += line + "\n";
  }
  EXPECT_EQ(replaced, static_cast<int>(replacements.size())) << "scenarios/paper.toml changed";
  const fs::path path = dir / (name + ".toml");
  WriteText(path, text);
  return path;
}

std::string RunOrDescribe(const std::string& args) {
  const CommandResult result = RunCli(args);
  return result.exit_code == 0 ? "" : "ipmc-swim " + args + ": " + result.output;
}

// A table laid out as "ipmc-swim sweep" writes it (sim/batch/sweep_table.h: point,
// swept keys, status ok | error, error, metrics), from three real runs and
// one failed point whose error has a comma and quotes in it.
std::string SweepTable(const fs::path& dir, std::string& failure) {
  struct Point {
    double frequency_Hz;
    std::string actuation;
  };
  const Point points[] = {{0.25, "distributed"}, {0.5, "distributed"}, {0.5, "single"}};
  std::string table =
      "point,waveform.frequency_Hz,actuation,status,error,mean_speed_along_mm_s,"
      "last_cycle_com_along_mm\n";
  int index = 0;
  for (const Point& point : points) {
    ++index;
    const std::string name = "sweep" + std::to_string(index);
    const fs::path scenario = ShortScenario(dir, name, point.frequency_Hz, 1, point.actuation);
    failure += RunOrDescribe("run " + Quoted(scenario) + " --out " + Quoted(dir / name));
    if (!failure.empty()) return "";
    const nlohmann::json summary = nlohmann::json::parse(ReadText(dir / name / "summary.json"));
    std::ostringstream row;
    row.precision(10);
    row << index << "," << point.frequency_Hz << "," << point.actuation << ",ok,,"
        << summary["mean_speed_along_mm_s"].get<double>() << ","
        << summary["per_cycle"].back()["com_along_mm"].get<double>() << "\n";
    table += row.str();
  }
  table +=
      "4,1,distributed,error,\"m.xml: simulation diverged at t = 0.26 s (reduce "
      "option \"\"timestep\"\", now 0.02 s)\",,\n";
  return table;
}

// Each output is made the first time a test asks for it (CTest runs every
// test in a process of its own, so a test makes only what it uses); a
// failure to make it fails the test that asked.
fs::path Made(const fs::path& path, const std::string& failure) {
  EXPECT_TRUE(failure.empty()) << failure;
  return path;
}

fs::path InputsDir() {
  static const fs::path dir = FreshDir("inputs");
  return dir;
}

struct ProgramOutputs {
  fs::path bode_csv() const {
    static const std::string failure =
        RunOrDescribe("bode --controller pid --links 3 --out " + Quoted(InputsDir() / "bode"));
    return Made(InputsDir() / "bode" / "bode.csv", failure);
  }
  fs::path step_csv() const {
    static const std::string failure =
        RunOrDescribe("step --controller pid --no-clamp --out " + Quoted(InputsDir() / "step"));
    return Made(InputsDir() / "step" / "step.csv", failure);
  }
  fs::path timeseries_csv() const {
    static const std::string failure = [] {
      const fs::path scenario = ShortScenario(InputsDir(), "closed_loop", 0.5, 2, "distributed");
      return RunOrDescribe("run " + Quoted(scenario) + " --out " + Quoted(InputsDir() / "run"));
    }();
    return Made(InputsDir() / "run" / "timeseries.csv", failure);
  }
  // The closed-loop run again with single actuation.
  fs::path single_run_dir() const {
    static const std::string failure = [] {
      const fs::path scenario = ShortScenario(InputsDir(), "single", 0.5, 2, "single");
      return RunOrDescribe("run " + Quoted(scenario) + " --out " + Quoted(InputsDir() / "single"));
    }();
    return Made(InputsDir() / "single", failure);
  }
  fs::path sweep_csv() const {
    static const std::string failure = [] {
      std::string made;
      WriteText(InputsDir() / "sweep.csv", SweepTable(InputsDir(), made));
      return made;
    }();
    return Made(InputsDir() / "sweep.csv", failure);
  }
};

// Files in `dir` whose name contains ".tmp." (an unfinished output).
int LeftoverTemporaries(const fs::path& dir) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    count += entry.path().filename().string().find(".tmp.") != std::string::npos;
  }
  return count;
}

bool EndsWith(const std::string& text, const std::string& tail) {
  return text.size() >= tail.size() &&
         text.compare(text.size() - tail.size(), tail.size(), tail) == 0;
}

// Runs "plot ARGS --out OUT" and checks that OUT is a whole file of the
// format its extension names (PNG: signature to IEND; PDF: %PDF- to
// %%EOF; SVG: an XML document whose root is <svg>); returns the output.
std::string ExpectFigure(const std::string& args, const fs::path& out) {
  const CommandResult result = RunCli("plot " + args + " --out " + Quoted(out));
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(fs::exists(out)) << result.output;
  if (!fs::exists(out)) return result.output;
  EXPECT_GT(fs::file_size(out), kMinFigureBytes) << out;
  const std::string bytes = ReadText(out);
  std::string extension = out.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".png") {
    EXPECT_EQ(bytes.substr(0, 8), std::string(kPngSignature, 8)) << out << " is not a PNG";
    EXPECT_TRUE(EndsWith(bytes, std::string(kPngEnd, 8))) << out << " does not end with IEND";
  } else if (extension == ".pdf") {
    EXPECT_EQ(bytes.rfind("%PDF-", 0), 0u) << out << " is not a PDF";
    EXPECT_NE(bytes.find("%%EOF", bytes.size() - 16), std::string::npos) << out << " is cut";
  } else {
    EXPECT_EQ(bytes.rfind("<?xml", 0), 0u) << out << " is not XML";
    EXPECT_NE(bytes.find("<svg"), std::string::npos) << out << " is not an SVG";
    EXPECT_NE(bytes.find("</svg>", bytes.size() - 16), std::string::npos) << out << " is cut";
  }
  EXPECT_EQ(LeftoverTemporaries(out.parent_path()), 0);
  return result.output;
}

// The text of an SVG with its markup removed and the entities that
// gnuplot writes decoded, as the reader sees it.
std::string SvgText(const fs::path& svg) {
  const std::string bytes = ReadText(svg);
  std::string text;
  bool in_tag = false;
  for (char c : bytes) {
    if (c == '<') in_tag = true;
    if (!in_tag) text += c;
    if (c == '>') {
      in_tag = false;
      text += ' ';
    }
  }
  for (const auto& [entity, character] : std::vector<std::pair<std::string, std::string>>{
           {"&apos;", "'"}, {"&quot;", "\""}, {"&lt;", "<"}, {"&gt;", ">"}, {"&amp;", "&"}}) {
    for (size_t at = text.find(entity); at != std::string::npos; at = text.find(entity, at)) {
      text.replace(at, entity.size(), character);
      at += character.size();
    }
  }
  return text;
}

// A refused plot: non-zero exit, one line naming each of `needles`, no
// output and no temporary file.
void ExpectRefused(const std::string& args, const fs::path& out,
                   const std::vector<std::string>& needles) {
  const CommandResult result = RunCli("plot " + args + " --out " + Quoted(out));
  EXPECT_NE(result.exit_code, 0) << result.output;
  EXPECT_EQ(CountLines(result.output), 1) << result.output;
  EXPECT_EQ(result.output.rfind("ipmc-swim: error: ", 0), 0u) << result.output;
  for (const std::string& needle : needles) {
    EXPECT_NE(result.output.find(needle), std::string::npos) << result.output;
  }
  EXPECT_FALSE(fs::exists(out));
  if (fs::exists(out.parent_path())) {
    EXPECT_EQ(LeftoverTemporaries(out.parent_path()), 0);
  }
}

// What a PDF page shows, rendered by poppler's pdftoppm (Debian
// poppler-utils) at 30 pixels per inch, between 10 % and 90 % of its
// height (the band of the panels, below the title): the fraction of dark
// pixels (luma below 128 of 255: text, axes, black curves) and of coloured
// ones (channels more than 80 apart: the curves and maps; axes, grid and
// text are grey). Both -1 if the page could not be rendered.
struct PageInk {
  double dark = -1.0, coloured = -1.0;
};

PageInk InkOf(const fs::path& pdf) {
  const fs::path prefix = pdf.parent_path() / (pdf.stem().string() + "_page");
  const std::string command =
      "pdftoppm -r 30 -singlefile " + Quoted(pdf) + " " + Quoted(prefix) + " 2>&1";
  if (std::system(command.c_str()) != 0) return {};
  const fs::path ppm = prefix.string() + ".ppm";
  std::ifstream in(ppm, std::ios::binary);
  std::string magic;
  int width = 0, height = 0, max_value = 0;
  in >> magic >> width >> height >> max_value;
  in.get();
  if (magic != "P6" || width <= 0 || height <= 0 || max_value != 255) return {};
  std::vector<unsigned char> pixels(static_cast<size_t>(width) * height * 3);
  in.read(reinterpret_cast<char*>(pixels.data()), static_cast<std::streamsize>(pixels.size()));
  if (in.gcount() != static_cast<std::streamsize>(pixels.size())) return {};
  in.close();
  fs::remove(ppm);
  size_t dark = 0, coloured = 0, counted = 0;
  for (int row = height / 10; row < height * 9 / 10; ++row) {
    for (int column = 0; column < width; ++column, ++counted) {
      const unsigned char* p = &pixels[(static_cast<size_t>(row) * width + column) * 3];
      const int luma = (299 * p[0] + 587 * p[1] + 114 * p[2]) / 1000;
      dark += luma < 128;
      coloured += std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) > 80;
    }
  }
  return {static_cast<double>(dark) / counted, static_cast<double>(coloured) / counted};
}

// The number after `label` in `text`; fails the test if there is none.
double NumberAfter(const std::string& text, const std::string& label) {
  const size_t at = text.find(label);
  double value = 0.0;
  EXPECT_TRUE(at != std::string::npos &&
              std::sscanf(text.c_str() + at + label.size(), "%lf", &value) == 1)
      << label << " not in " << text;
  return value;
}

// Tests that use the program's outputs (each made on first use).
class PlotCommandTest : public ::testing::Test {
 protected:
  const ProgramOutputs outputs{};
};

TEST_F(PlotCommandTest, BodeOfEveryCurveAndOfTheControllerAlone) {
  const fs::path dir = FreshDir("bode");
  ExpectFigure("bode " + Quoted(outputs.bode_csv()), dir / "bode.png");
  ExpectFigure("bode " + Quoted(outputs.bode_csv()) + " --curves controller --title 'Fig. 9'",
               dir / "controller.png");
}

TEST_F(PlotCommandTest, Step) {
  ExpectFigure("step " + Quoted(outputs.step_csv()), FreshDir("step") / "step.png");
}

// Per link an error panel with the RMS of measured - reference over the
// steady cycles (here cycle 2 of two, t >= one period), printed (4
// significant digits) and written in the panel.
TEST_F(PlotCommandTest, Tracking) {
  const fs::path dir = FreshDir("tracking");
  const std::string printed =
      ExpectFigure("tracking " + Quoted(outputs.timeseries_csv()), dir / "t.svg");
  EXPECT_NE(SvgText(dir / "t.svg").find("measured - reference; RMS over cycle 2: "),
            std::string::npos);
  const ipmc::CsvTable table = ipmc::CsvTable::Read(outputs.timeseries_csv().string());
  const std::vector<double> t = table.Numbers("time_s");
  const double period_s =
      nlohmann::json::parse(ReadText(outputs.timeseries_csv().parent_path() / "summary.json"))
          ["period_s"]
              .get<double>();
  for (int q = 1; q <= 3; ++q) {
    const std::vector<double> reference = table.Numbers("reference" + std::to_string(q) + "_mm");
    const std::vector<double> measured = table.Numbers("measured" + std::to_string(q) + "_mm");
    double sum = 0.0;
    int count = 0;
    for (size_t i = 0; i < t.size(); ++i) {
      if (t[i] < period_s) continue;
      sum += (measured[i] - reference[i]) * (measured[i] - reference[i]);
      ++count;
    }
    const double rms = std::sqrt(sum / count);
    const std::string note = "link " + std::to_string(q) + ": tracking error RMS over cycle 2: ";
    EXPECT_NEAR(NumberAfter(printed, note), rms, 5e-4 * rms) << printed;
  }
}

// The clamp's shade covers the clamped samples and nothing between them:
// one box per run of samples at +-V_max, half a sample beyond its ends
// (ClampIntervals), each drawn apart in the SVG. A record of 100 samples
// over 99 s with the voltage at the clamp at samples 10-19, 50 and 90-99
// gives boxes over [9.5, 19.5], [49.5, 50.5] and [89.5, 99] s.
TEST(ClampShadeTest, CoversOnlyTheClampedSamples) {
  std::vector<double> t, v;
  for (int i = 0; i < 100; ++i) {
    t.push_back(i);
    const bool at_clamp = (i >= 10 && i < 20) || i == 50 || i >= 90;
    v.push_back(at_clamp ? (i == 50 ? -6.0 : 6.0) : 3.0 * std::sin(0.1 * i));
  }
  const auto intervals = ipmc::figure_parts::ClampIntervals(t, v, true, 6.0);
  ASSERT_EQ(intervals.size(), 3u);
  const double expected[3][3] = {{9.5, 19.5, 10}, {49.5, 50.5, 1}, {89.5, 99.0, 10}};
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(intervals[i].start_s, expected[i][0]);
    EXPECT_EQ(intervals[i].end_s, expected[i][1]);
    EXPECT_EQ(intervals[i].samples, static_cast<size_t>(expected[i][2]));
  }
  EXPECT_TRUE(ipmc::figure_parts::ClampIntervals(t, v, false, 6.0).empty());

  // The figure: the shade's polygons (the key's swatch besides) span the
  // boxes' widths in proportion 10 : 1 : 9.5.
  const fs::path dir = FreshDir("clamp_shade");
  std::string csv = "time_s,reference1_mm,measured1_mm,voltage1_V\n";
  for (int i = 0; i < 100; ++i) {
    csv += std::to_string(t[i]) + ",0.1,0.09," + std::to_string(v[i]) + "\n";
  }
  WriteText(dir / "timeseries.csv", csv);
  WriteText(dir / "summary.json",
            R"({"clamp_enabled": true, "v_max_V": 6.0, "period_s": 50.0})");
  ExpectFigure("tracking " + Quoted(dir / "timeseries.csv"), dir / "tracking.svg");
  const std::string svg = ReadText(dir / "tracking.svg");
  const std::string shade = "<polygon fill = 'rgb(246, 213, 209)' points = '";
  std::vector<double> widths;
  for (size_t at = svg.find(shade); at != std::string::npos; at = svg.find(shade, at + 1)) {
    double x0 = 0, y0 = 0, x1 = 0;
    ASSERT_EQ(std::sscanf(svg.c_str() + at + shade.size(), "%lf,%lf %lf", &x0, &y0, &x1), 3);
    widths.push_back(x1 - x0);
  }
  ASSERT_EQ(widths.size(), 4u) << "three boxes and the key's swatch";
  EXPECT_NEAR(widths[1] / widths[0], 0.1, 0.02);
  EXPECT_NEAR(widths[2] / widths[0], 0.95, 0.02);
}

// Default instants (the last period from summary.json) and chosen ones;
// the continuous wave drawn apart from its projection onto the links.
TEST_F(PlotCommandTest, Waveform) {
  const fs::path dir = FreshDir("waveform");
  ExpectFigure("waveform " + Quoted(outputs.timeseries_csv()), dir / "default.png");
  ExpectFigure("waveform " + Quoted(outputs.timeseries_csv()), dir / "default.svg");
  const std::string text = SvgText(dir / "default.svg");
  for (const char* shown : {"wave y(x, t)", "projected onto the links", "realised"}) {
    EXPECT_NE(text.find(shown), std::string::npos) << shown << " not in " << text;
  }
  ExpectFigure("waveform " + Quoted(outputs.timeseries_csv()) + " --times-s 2.5,3,3.5",
               dir / "chosen.png");
}

// Ideal, realised and their difference, against the distance along the
// body (no blank beyond a bent body's reach along x), time labelled.
TEST_F(PlotCommandTest, SurfaceIntoANewDirectory) {
  const fs::path dir = FreshDir("surface");
  ExpectFigure("surface " + Quoted(outputs.timeseries_csv()) + " --max-lines 40",
               dir / "new" / "surface.png");
  const std::string printed =
      ExpectFigure("surface " + Quoted(outputs.timeseries_csv()), dir / "surface.svg");
  EXPECT_NE(printed.find("realised - ideal: at most "), std::string::npos) << printed;
  const std::string text = SvgText(dir / "surface.svg");
  for (const std::string& shown :
       {std::string("realised - ideal"), std::string("s along the body [mm]"),
        ipmc::AxisLabel("time_s")}) {
    EXPECT_NE(text.find(shown), std::string::npos) << shown << " not in " << text;
  }
}

TEST_F(PlotCommandTest, Trajectory) {
  ExpectFigure("trajectory " + Quoted(outputs.timeseries_csv()), FreshDir("trajectory") / "t.png");
}

// Two runs that differ in their actuation: the legend and the title say
// so, the notes give each run's last cycle and steady tracking error.
TEST_F(PlotCommandTest, CompareNamesWhatDiffers) {
  const fs::path dir = FreshDir("compare");
  const std::string run = outputs.timeseries_csv().parent_path().string();
  const std::string printed =
      ExpectFigure("compare " + Quoted(run) + " " + Quoted(outputs.single_run_dir()),
                   dir / "compare.svg");
  EXPECT_NE(printed.find("Comparison of 2 runs: differing in actuation"), std::string::npos)
      << printed;
  EXPECT_NE(printed.find("run 1 (actuation = distributed): last cycle"), std::string::npos)
      << printed;
  EXPECT_NE(printed.find("RMS tracking error over cycle 2, per link"), std::string::npos)
      << printed;
  const std::string text = SvgText(dir / "compare.svg");
  for (const char* shown : {"actuation = distributed", "actuation = single",
                            "link 3: tracking error, measured - reference", "link 1: voltage",
                            "displacement per cycle", "RMS over cycle 2: "}) {
    EXPECT_NE(text.find(shown), std::string::npos) << shown << " not in " << text;
  }
  ExpectFigure("compare " + Quoted(run) + " " + Quoted(outputs.single_run_dir()),
               dir / "compare.pdf");
  // --labels names the runs instead, one per run.
  ExpectFigure("compare " + Quoted(run) + " " + Quoted(outputs.single_run_dir()) +
                   " --labels 'all links driven' 'link 1 alone'",
               dir / "labels.svg");
  EXPECT_NE(SvgText(dir / "labels.svg").find("link 1 alone"), std::string::npos);
  ExpectRefused("compare " + Quoted(run) + " " + Quoted(outputs.single_run_dir()) +
                    " --labels one",
                dir / "one_label.png", {"--labels gives 1 labels for 2 runs"});
  ExpectRefused("compare " + Quoted(run), dir / "one.png", {"needs 2 to 8 run directories"});
  const fs::path empty = FreshDir("compare_empty");
  ExpectRefused("compare " + Quoted(run) + " " + Quoted(empty), dir / "empty.png",
                {empty.string(), "no timeseries.csv"});
  ExpectRefused("tracking " + Quoted(outputs.timeseries_csv()) + " " +
                    Quoted(outputs.timeseries_csv()),
                dir / "two.png", {"needs one input, got 2"});
}

// One figure in each format, the extension in either case.
TEST_F(PlotCommandTest, FormatFollowsTheExtension) {
  const fs::path dir = FreshDir("formats");
  for (const char* name : {"tracking.pdf", "tracking.svg", "tracking.png", "upper.PDF"}) {
    ExpectFigure("tracking " + Quoted(outputs.timeseries_csv()), dir / name);
  }
}

// The default title says what is drawn and of which run (summary.json
// beside the input: PID, the clamp, the actuation), never where the
// input is; the caller's title replaces it.
TEST_F(PlotCommandTest, TitleSaysWhatIsShownNotWhere) {
  const fs::path dir = FreshDir("title");
  const std::string printed =
      ExpectFigure("tracking " + Quoted(outputs.timeseries_csv()), dir / "tracking.svg");
  const std::string text = SvgText(dir / "tracking.svg");
  for (const char* shown : {"Tracking of each link's relative tip deflection",
                            "PID, clamp +-6 V, distributed actuation", "link 3"}) {
    EXPECT_NE(text.find(shown), std::string::npos) << shown << " not in " << text;
  }
  const std::string folder = outputs.timeseries_csv().parent_path().string();
  EXPECT_EQ(text.find(folder), std::string::npos) << text;
  EXPECT_EQ(text.find("timeseries.csv"), std::string::npos) << text;
  const std::string title_line = printed.substr(printed.find('\n') + 1);
  EXPECT_EQ(title_line.find('/'), std::string::npos) << printed;
  ExpectFigure("tracking " + Quoted(outputs.timeseries_csv()) + " --title 'Fig. 12a'",
               dir / "own.svg");
  EXPECT_NE(SvgText(dir / "own.svg").find("Fig. 12a"), std::string::npos);
}

// Sweep axes carry the labels of the table, not the raw column names.
TEST_F(PlotCommandTest, SweepAxesLabelledFromTheTable) {
  const fs::path out = FreshDir("labels") / "sweep.svg";
  ExpectFigure("sweep " + Quoted(outputs.sweep_csv()) +
                   " --x waveform.frequency_Hz --y mean_speed_along_mm_s --group actuation",
               out);
  const std::string text = SvgText(out);
  for (const char* column : {"mean_speed_along_mm_s", "waveform.frequency_Hz", "actuation"}) {
    EXPECT_NE(text.find(ipmc::AxisLabel(column)), std::string::npos) << column << ": " << text;
  }
  EXPECT_EQ(text.find("mean_speed_along_mm_s"), std::string::npos) << text;
  EXPECT_EQ(text.find("frequency_Hz"), std::string::npos) << text;
}

TEST(AxisLabelTest, TableNumberedColumnsAndUnitSuffixes) {
  EXPECT_EQ(ipmc::AxisLabel("mean_speed_along_mm_s"), "mean speed along the swimming axis [mm/s]");
  EXPECT_EQ(ipmc::AxisLabel("voltage2_V"), "link 2 voltage [V]");
  EXPECT_EQ(ipmc::AxisLabel("q3_rad"), "joint 3 angle [rad]");
  EXPECT_EQ(ipmc::AxisLabel("link3_iae_mm_s"), "link 3 IAE [mm s]");
  EXPECT_EQ(ipmc::AxisLabel("link_lengths_mm[1]"), "link 2 length [mm]");
  EXPECT_EQ(ipmc::AxisLabel("fluid.density_kg_m3"), "fluid density [kg/m^3]");
}


// The margins the Bode figure marks are those the bode command found by
// root search on the exact response (bode.json), printed in the same
// digits: for the PID and link 3 a phase margin of 54.14 deg at
// 31.117 rad/s and no finite gain margin, for the fractional integrator
// also a gain margin of 7.88 dB at 20.649 rad/s.
TEST_F(PlotCommandTest, BodeMarginsAreTheBodeCommands) {
  const fs::path dir = FreshDir("margins");
  const std::string pid = ExpectFigure("bode " + Quoted(outputs.bode_csv()), dir / "pid.png");
  const CommandResult pid_exact = RunCli("bode --controller pid --links 3");
  ASSERT_EQ(pid_exact.exit_code, 0) << pid_exact.output;
  EXPECT_EQ(NumberAfter(pid, "Pm = "), NumberAfter(pid_exact.output, "phase margin: "));
  EXPECT_EQ(NumberAfter(pid, "deg (at "), NumberAfter(pid_exact.output, "gain crossover: "));
  EXPECT_NE(pid.find("Pm = 54.14 deg (at 31.117 rad/s)"), std::string::npos) << pid;
  EXPECT_NE(pid.find("Gm = inf"), std::string::npos) << pid;

  const CommandResult fractional =
      RunCli("bode --controller fractional --links 3 --out " + Quoted(dir / "fractional"));
  ASSERT_EQ(fractional.exit_code, 0) << fractional.output;
  const std::string figure =
      ExpectFigure("bode " + Quoted(dir / "fractional" / "bode.csv"), dir / "fractional.png");
  EXPECT_EQ(NumberAfter(figure, "Pm = "), NumberAfter(fractional.output, "phase margin: "));
  EXPECT_EQ(NumberAfter(figure, "Gm = "), NumberAfter(fractional.output, "gain margin: "));
  EXPECT_EQ(NumberAfter(figure, "dB (at "), NumberAfter(fractional.output, "dB at "));
}

// Without bode.json beside bode.csv the figure knows no margins and says
// so, rather than compute others from the grid.
TEST_F(PlotCommandTest, BodeWithoutItsJsonMarksNoMargins) {
  const fs::path dir = FreshDir("margins_unknown");
  fs::copy_file(outputs.bode_csv(), dir / "bode.csv");
  const std::string figure = ExpectFigure("bode " + Quoted(dir / "bode.csv"), dir / "bode.png");
  EXPECT_NE(figure.find("no margins marked"), std::string::npos) << figure;
  EXPECT_EQ(figure.find("Pm = "), std::string::npos) << figure;
}

// Every kind as a PDF, rendered by pdftoppm: each page has axes and text
// (dark) and curves or maps (coloured) in its band. A blank page has
// neither; one axis box with its title and labels and no curve (gnuplot,
// 7 x 4.5 in) is 0.99 % dark and has no coloured pixel. Measured on these
// figures: dark 1.1 % (sweep, three points) to 7.1 % (tracking), coloured
// 0.20 % (sweep) to 6.0 % (surface).
TEST_F(PlotCommandTest, EveryPdfRendersWithSomethingDrawn) {
  const fs::path dir = FreshDir("pdf_pages");
  const std::string run = outputs.timeseries_csv().parent_path().string();
  const std::vector<std::pair<std::string, std::string>> figures = {
      {"bode", "bode " + Quoted(outputs.bode_csv())},
      {"step", "step " + Quoted(outputs.step_csv())},
      {"tracking", "tracking " + Quoted(outputs.timeseries_csv())},
      {"waveform", "waveform " + Quoted(outputs.timeseries_csv())},
      {"surface", "surface " + Quoted(outputs.timeseries_csv())},
      {"trajectory", "trajectory " + Quoted(outputs.timeseries_csv())},
      {"sweep", "sweep " + Quoted(outputs.sweep_csv()) +
                    " --x waveform.frequency_Hz --y mean_speed_along_mm_s --group actuation"},
      {"compare", "compare " + Quoted(run) + " " + Quoted(outputs.single_run_dir())}};
  for (const auto& [name, args] : figures) {
    const fs::path pdf = dir / (name + ".pdf");
    ExpectFigure(args, pdf);
    const PageInk ink = InkOf(pdf);
    std::printf("%s: dark %.4f, coloured %.4f\n", name.c_str(), ink.dark, ink.coloured);
    EXPECT_GT(ink.dark, 0.005) << name << ": no axes or text";
    EXPECT_LT(ink.dark, 0.5) << name << ": filled";
    EXPECT_GT(ink.coloured, 0.0005) << name << ": no curve";
  }
}

TEST_F(PlotCommandTest, UnknownExtensionIsRefusedAndLeavesNothing) {
  const fs::path dir = FreshDir("extension");
  for (const char* name : {"tracking.jpg", "tracking"}) {
    ExpectRefused("tracking " + Quoted(outputs.timeseries_csv()), dir / name,
                  {(dir / name).string(), "unknown figure format", ".pdf, .svg, .png"});
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

// Numeric x with one curve per actuation, and a categorical x; the failed
// point (no metrics) is skipped.
TEST_F(PlotCommandTest, SweepNumericAndCategorical) {
  const fs::path dir = FreshDir("sweep");
  ExpectFigure("sweep " + Quoted(outputs.sweep_csv()) +
                   " --x waveform.frequency_Hz --y mean_speed_along_mm_s --group actuation --log-x",
               dir / "numeric.png");
  ExpectFigure("sweep " + Quoted(outputs.sweep_csv()) +
                   " --x actuation --y last_cycle_com_along_mm --group waveform.frequency_Hz",
               dir / "categorical.png");
}

TEST_F(PlotCommandTest, MissingColumnNamesTheFileAndTheColumn) {
  const fs::path dir = FreshDir("missing");
  std::string step = ReadText(outputs.step_csv());
  step.replace(step.find("reference_model"), std::strlen("reference_model"), "model");
  const fs::path edited = dir / "step.csv";
  WriteText(edited, step);
  ExpectRefused("step " + Quoted(edited), dir / "step.png", {edited.string(), "reference_model"});
  ExpectRefused("sweep " + Quoted(outputs.sweep_csv()) + " --x waveform.frequency_Hz --y speed",
                dir / "sweep.png", {outputs.sweep_csv().string(), "'speed'"});
  ExpectRefused("tracking " + Quoted(outputs.bode_csv()), dir / "tracking.png",
                {outputs.bode_csv().string(), "reference1_mm"});
  ExpectRefused("trajectory " + Quoted(outputs.bode_csv()), dir / "trajectory.png",
                {outputs.bode_csv().string(), "time_s"});
}

TEST_F(PlotCommandTest, OptionOfAnotherKindIsRefused) {
  const fs::path dir = FreshDir("option");
  ExpectRefused("bode " + Quoted(outputs.bode_csv()) + " --x w_rad_s", dir / "bode.png",
                {"--x", "sweep"});
  ExpectRefused("sweep " + Quoted(outputs.sweep_csv()) + " --x actuation", dir / "sweep.png",
                {"--y"});
}

// gnuplot's own failure (a log axis with no positive value) is reported
// with its message.
TEST(PlotCommandFailureTest, GnuplotFailureLeavesNoFile) {
  const fs::path dir = FreshDir("gnuplot_failure");
  WriteText(dir / "negative.csv", "point,a,status,error,m\n1,1,ok,,-1\n2,2,ok,,-2\n");
  ExpectRefused("sweep " + Quoted(dir / "negative.csv") + " --x a --y m --log-y",
                dir / "negative.png", {"gnuplot failed", "negative.csv"});
}

// A gait's outputs (one 1 Hz cycle): tracking draws the joints, the
// waveform and the map draw the ideal body from the joint references.
TEST(PlotGaitTest, TrackingWaveformSurface) {
  const fs::path dir = FreshDir("gait");
  const CommandResult gait =
      RunCli("gait --model '" + std::string(IPMC_SWIM_SOURCE_DIR) +
             "/models/flagellum3.xml' --frequency-hz 1 --cycles 1 --out " + Quoted(dir / "run"));
  ASSERT_EQ(gait.exit_code, 0) << gait.output;
  const std::string csv = Quoted(dir / "run" / "timeseries.csv");
  ExpectFigure("tracking " + csv, dir / "tracking.svg");
  EXPECT_NE(SvgText(dir / "tracking.svg").find(ipmc::AxisLabel("q1_rad")), std::string::npos);
  ExpectFigure("waveform " + csv, dir / "waveform.svg");
  EXPECT_NE(SvgText(dir / "waveform.svg").find("ideal (dashed)"), std::string::npos);
  ExpectFigure("surface " + csv, dir / "surface.png");
}

// Fig. 7 from a short chirp on the bench (10 s, 0.5 to 20 Hz) identified
// over 3 to 50 rad/s: the measured response, the coherence and both fits.
TEST(PlotIdentificationTest, MeasuredResponseCoherenceAndFits) {
  const fs::path dir = FreshDir("identification");
  const CommandResult bench =
      RunCli("bench --signal chirp --links 1 --duration-s 10 --f0-hz 0.5 --f1-hz 20 --out " +
             Quoted(dir / "chirp.csv"));
  ASSERT_EQ(bench.exit_code, 0) << bench.output;
  const CommandResult identify = RunCli(
      "identify " + Quoted(dir / "chirp.csv") +
      " --input voltage1_V --output relative1_mm --band-rad-s 3,50 --out " + Quoted(dir / "id"));
  ASSERT_EQ(identify.exit_code, 0) << identify.output;
  ExpectFigure("identification " + Quoted(dir / "id" / "response.csv"), dir / "fig7.svg");
  const std::string text = SvgText(dir / "fig7.svg");
  for (const char* shown : {"coherence", "G1 (eq. 5)", "G2 (eq. 6)", "in the fits' band",
                            "link 1 relative tip deflection per link 1 voltage"}) {
    EXPECT_NE(text.find(shown), std::string::npos) << shown << " not in " << text;
  }
}

}  // namespace
