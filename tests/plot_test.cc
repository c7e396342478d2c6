// The plot subcommand: every figure kind draws a PNG from the program's own
// outputs (bode.csv, step.csv, a closed-loop timeseries.csv, a sweep
// table), generated here by running ipmc-swim; a missing column, an option
// of another kind or a failing gnuplot gives one line and no file.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

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

// The program's outputs, made once for all tests.
struct ProgramOutputs {
  fs::path bode_csv, step_csv, timeseries_csv, sweep_csv;
  std::string failure;  // empty if every run succeeded
};

std::string RunOrDescribe(const std::string& args) {
  const CommandResult result = RunCli(args);
  return result.exit_code == 0 ? "" : "ipmc-swim " + args + ": " + result.output;
}

// A table laid out as "ipmc-swim sweep" writes it (sim/batch/sweep.h: point,
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
  table += "4,1,distributed,error,\"m.xml: simulation diverged at t = 0.26 s (reduce "
           "option \"\"timestep\"\", now 0.02 s)\",,\n";
  return table;
}

const ProgramOutputs& Outputs() {
  static const ProgramOutputs outputs = [] {
    ProgramOutputs o;
    const fs::path dir = FreshDir("inputs");
    o.failure += RunOrDescribe("bode --controller pid --out " + Quoted(dir / "bode"));
    o.failure += RunOrDescribe("step --controller pid --no-clamp --out " + Quoted(dir / "step"));
    const fs::path scenario = ShortScenario(dir, "closed_loop", 0.5, 2, "distributed");
    o.failure += RunOrDescribe("run " + Quoted(scenario) + " --out " + Quoted(dir / "run"));
    const std::string sweep = SweepTable(dir, o.failure);
    WriteText(dir / "sweep.csv", sweep);
    o.bode_csv = dir / "bode" / "bode.csv";
    o.step_csv = dir / "step" / "step.csv";
    o.timeseries_csv = dir / "run" / "timeseries.csv";
    o.sweep_csv = dir / "sweep.csv";
    return o;
  }();
  return outputs;
}

// Files in `dir` whose name contains ".tmp." (an unfinished output).
int LeftoverTemporaries(const fs::path& dir) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    count += entry.path().filename().string().find(".tmp.") != std::string::npos;
  }
  return count;
}

// Runs "plot ARGS --out OUT" and checks that OUT is a PNG of a figure.
void ExpectFigure(const std::string& args, const fs::path& out) {
  const CommandResult result = RunCli("plot " + args + " --out " + Quoted(out));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  ASSERT_TRUE(fs::exists(out)) << result.output;
  EXPECT_GT(fs::file_size(out), kMinFigureBytes) << out;
  const std::string head = ReadText(out).substr(0, 8);
  EXPECT_EQ(head, std::string(kPngSignature, 8)) << out << " is not a PNG";
  EXPECT_EQ(LeftoverTemporaries(out.parent_path()), 0);
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

// Tests that need the program's outputs; they stop if making them failed.
class PlotCli : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(outputs.failure.empty()) << outputs.failure; }
  const ProgramOutputs& outputs = Outputs();
};

TEST_F(PlotCli, BodeOfEveryCurveAndOfTheControllerAlone) {
  const fs::path dir = FreshDir("bode");
  ExpectFigure("bode " + Quoted(outputs.bode_csv), dir / "bode.png");
  ExpectFigure("bode " + Quoted(outputs.bode_csv) + " --curves controller --title 'Fig. 9'",
               dir / "controller.png");
}

TEST_F(PlotCli, Step) {
  ExpectFigure("step " + Quoted(outputs.step_csv), FreshDir("step") / "step.png");
}

TEST_F(PlotCli, Tracking) {
  ExpectFigure("tracking " + Quoted(outputs.timeseries_csv), FreshDir("tracking") / "t.png");
}

// Default instants (the last period from summary.json) and chosen ones.
TEST_F(PlotCli, Waveform) {
  const fs::path dir = FreshDir("waveform");
  ExpectFigure("waveform " + Quoted(outputs.timeseries_csv), dir / "default.png");
  ExpectFigure("waveform " + Quoted(outputs.timeseries_csv) + " --times-s 2.5,3,3.5",
               dir / "chosen.png");
}

TEST_F(PlotCli, SurfaceIntoANewDirectory) {
  ExpectFigure("surface " + Quoted(outputs.timeseries_csv) + " --max-lines 40",
               FreshDir("surface") / "new" / "surface.png");
}

// Numeric x with one curve per actuation, and a categorical x; the failed
// point (no metrics) is skipped.
TEST_F(PlotCli, SweepNumericAndCategorical) {
  const fs::path dir = FreshDir("sweep");
  ExpectFigure("sweep " + Quoted(outputs.sweep_csv) +
                   " --x waveform.frequency_Hz --y mean_speed_along_mm_s --group actuation --log-x",
               dir / "numeric.png");
  ExpectFigure("sweep " + Quoted(outputs.sweep_csv) +
                   " --x actuation --y last_cycle_com_along_mm --group waveform.frequency_Hz",
               dir / "categorical.png");
}

TEST_F(PlotCli, MissingColumnNamesTheFileAndTheColumn) {
  const fs::path dir = FreshDir("missing");
  std::string step = ReadText(outputs.step_csv);
  step.replace(step.find("reference_model"), std::strlen("reference_model"), "model");
  const fs::path edited = dir / "step.csv";
  WriteText(edited, step);
  ExpectRefused("step " + Quoted(edited), dir / "step.png", {edited.string(), "reference_model"});
  ExpectRefused("sweep " + Quoted(outputs.sweep_csv) + " --x waveform.frequency_Hz --y speed",
                dir / "sweep.png", {outputs.sweep_csv.string(), "'speed'"});
  ExpectRefused("tracking " + Quoted(outputs.bode_csv), dir / "tracking.png",
                {outputs.bode_csv.string(), "reference1_mm"});
}

TEST_F(PlotCli, OptionOfAnotherKindIsRefused) {
  const fs::path dir = FreshDir("option");
  ExpectRefused("bode " + Quoted(outputs.bode_csv) + " --x w_rad_s", dir / "bode.png",
                {"--x", "sweep"});
  ExpectRefused("sweep " + Quoted(outputs.sweep_csv) + " --x actuation", dir / "sweep.png",
                {"--y"});
}

// gnuplot's own failure (a log axis with no positive value) is reported
// with its message.
TEST(PlotCliFailure, GnuplotFailureLeavesNoFile) {
  const fs::path dir = FreshDir("gnuplot_failure");
  WriteText(dir / "negative.csv", "point,a,status,error,m\n1,1,ok,,-1\n2,2,ok,,-2\n");
  ExpectRefused("sweep " + Quoted(dir / "negative.csv") + " --x a --y m --log-y",
                dir / "negative.png", {"gnuplot failed", "negative.csv"});
}

}  // namespace
