// The ipmc-swim program: outputs, and one-line errors with no partial files
// on bad input.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/cli_util.h"

namespace {

namespace fs = std::filesystem;
using ipmc::testing::CommandResult;
using ipmc::testing::CountLines;
using ipmc::testing::RunCli;

// Directories are named after the suite.
fs::path FreshDir(const std::string& name) { return ipmc::testing::FreshDir("cli_" + name); }

std::string Model(const std::string& name) {
  return std::string(IPMC_SWIM_SOURCE_DIR) + "/models/" + name;
}

// A bad-input run: non-zero exit, one line naming `what`, no output files.
void ExpectOneLineError(const CommandResult& result, const std::string& what,
                        const fs::path& out_dir) {
  EXPECT_NE(result.exit_code, 0) << result.output;
  EXPECT_EQ(CountLines(result.output), 1) << result.output;
  EXPECT_NE(result.output.find(what), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(out_dir / "summary.json"));
  EXPECT_FALSE(fs::exists(out_dir / "timeseries.csv"));
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

TEST(CliTest, GaitWritesPerCycleTableCsvAndJson) {
  const fs::path dir = FreshDir("gait");
  const fs::path model = dir / "fast.xml";
  // The paper's flagellum with a coarser step and a faster gait keeps this quick.
  ASSERT_EQ(RunCli("generate --timestep-s 5e-4 --out " + model.string()).exit_code, 0);
  const CommandResult result = RunCli("gait --model " + model.string() +
                                      " --frequency-hz 0.5 --cycles 2 --out " + (dir / "out").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("com_along_mm"), std::string::npos);
  EXPECT_NE(result.output.find("Reynolds number"), std::string::npos);
  std::ifstream json_file(dir / "out" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(json_file);
  EXPECT_EQ(summary["per_cycle"].size(), 2u);
  EXPECT_GT(summary["per_cycle"][1]["com_along_mm"].get<double>(), 0.0);
  std::ifstream csv(dir / "out" / "timeseries.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("time_s,com_x_mm,com_y_mm,head_x_mm,head_y_mm,yaw_rad,q_ref1_rad", 0), 0u);
}

TEST(CliTest, MissingModelFile) {
  const fs::path dir = FreshDir("missing");
  ExpectOneLineError(RunCli("gait --model " + (dir / "nope.xml").string() + " --out " +
                            (dir / "out").string()),
                     "nope.xml: cannot open model file", dir / "out");
}

TEST(CliTest, MalformedModelFile) {
  const fs::path dir = FreshDir("malformed");
  WriteText(dir / "bad.xml", "<mujoco><worldbody><body></worldbody></mujoco>");
  ExpectOneLineError(RunCli("gait --model " + (dir / "bad.xml").string() + " --out " +
                            (dir / "out").string()),
                     "bad.xml:", dir / "out");
}

// The paper's model with one custom field changed.
void WriteModelWithField(const fs::path& path, const std::string& from, const std::string& to) {
  std::ifstream in(Model("flagellum3.xml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string xml = text.str();
  const size_t at = xml.find(from);
  ASSERT_NE(at, std::string::npos);
  xml.replace(at, from.size(), to);
  WriteText(path, xml);
}

TEST(CliTest, NegativeViscosity) {
  const fs::path dir = FreshDir("negative_viscosity");
  WriteModelWithField(dir / "m.xml", R"(data="0.001")", R"(data="-0.001")");
  ExpectOneLineError(RunCli("gait --model " + (dir / "m.xml").string() + " --out " +
                            (dir / "out").string()),
                     "m.xml: rft drag: ipmc_rft_viscosity_Pa_s must be finite and > 0", dir / "out");
}

TEST(CliTest, MissingViscosity) {
  const fs::path dir = FreshDir("missing_viscosity");
  WriteModelWithField(dir / "m.xml", R"(<numeric name="ipmc_rft_viscosity_Pa_s" data="0.001"/>)", "");
  ExpectOneLineError(RunCli("gait --model " + (dir / "m.xml").string() + " --out " +
                            (dir / "out").string()),
                     "ipmc_rft_viscosity_Pa_s is missing", dir / "out");
}

TEST(CliTest, NanCoefficient) {
  const fs::path dir = FreshDir("nan_coefficient");
  WriteModelWithField(dir / "m.xml", R"(name="ipmc_rft_wavelength_m" data="0.032")",
                      R"(name="ipmc_rft_wavelength_m" data="nan")");
  ExpectOneLineError(RunCli("gait --model " + (dir / "m.xml").string() + " --out " +
                            (dir / "out").string()),
                     "'ipmc_rft_wavelength_m' must be finite", dir / "out");
}

TEST(CliTest, UnknownOption) {
  const fs::path dir = FreshDir("unknown_option");
  ExpectOneLineError(RunCli("gait --model " + Model("flagellum3.xml") + " --speed 3 --out " +
                            (dir / "out").string()),
                     "--speed", dir / "out");
}

TEST(CliTest, GaitCsvWithWrongColumnCount) {
  const fs::path dir = FreshDir("csv_columns");
  WriteText(dir / "gait.csv", "time_s,q1,q2,q3\n0,0,0,0\n1,0.1,0.2\n");
  ExpectOneLineError(RunCli("gait --model " + Model("flagellum3.xml") + " --gait csv --csv " +
                            (dir / "gait.csv").string() + " --out " + (dir / "out").string()),
                     "gait.csv:3: expected 4 columns", dir / "out");
}

TEST(CliTest, OutOfRangeFrequency) {
  const fs::path dir = FreshDir("frequency");
  ExpectOneLineError(RunCli("gait --model " + Model("flagellum3.xml") +
                            " --frequency-hz -1 --out " + (dir / "out").string()),
                     "--frequency-hz must be finite and > 0 (got -1)", dir / "out");
}

TEST(CliTest, UnstableTimeStepIsReportedAsDivergence) {
  const fs::path dir = FreshDir("diverge");
  // Explicit Euler with 20 ms steps cannot hold the 450 rad/s hinge mode.
  ASSERT_EQ(RunCli("generate --timestep-s 0.02 --integrator Euler --out " +
                   (dir / "m.xml").string()).exit_code, 0);
  const CommandResult result = RunCli("gait --model " + (dir / "m.xml").string() +
                                      " --cycles 1 --out " + (dir / "out").string());
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.output.find("simulation diverged"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(dir / "out" / "summary.json"));
}

}  // namespace

namespace {

TEST(CliTest, BenchSineWritesTheLaserRecord) {
  const fs::path dir = FreshDir("bench");
  const CommandResult result = RunCli("bench --signal sine --frequency-hz 1 --duration-s 2 --links 1,3 --out " +
                                      (dir / "bench.csv").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::ifstream csv(dir / "bench.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("time_s,voltage1_V,relative1_mm,tip1_lateral_mm,free1_mm", 0), 0u);
  int rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_EQ(rows, 2000);  // 2 s at 1 kHz
}

TEST(CliTest, BenchNonFiniteVoltage) {
  const fs::path dir = FreshDir("bench_nan");
  ExpectOneLineError(RunCli("bench --amplitude-v nan --out " + (dir / "bench.csv").string()),
                     "--amplitude-v must be finite", dir);
  EXPECT_FALSE(fs::exists(dir / "bench.csv"));
}

TEST(CliTest, BenchNegativeB2) {
  const fs::path dir = FreshDir("bench_b2");
  WriteModelWithField(dir / "m.xml", R"(<text name="ipmc_model" data="g1"/>)",
                      R"(<text name="ipmc_model" data="g1"/>
    <numeric name="ipmc_b2_s2" data="1.62e-3 -1.61e-3 2.13e-3"/>)");
  ExpectOneLineError(RunCli("bench --model " + (dir / "m.xml").string() + " --out " +
                            (dir / "bench.csv").string()),
                     "link 2: ipmc link: b2_s2 must be finite and >= 0", dir);
  EXPECT_FALSE(fs::exists(dir / "bench.csv"));
}

TEST(CliTest, BenchAlphaOutOfRange) {
  const fs::path dir = FreshDir("bench_alpha");
  WriteModelWithField(dir / "m.xml", R"(<text name="ipmc_model" data="g1"/>)",
                      R"(<text name="ipmc_model" data="g2"/>
    <numeric name="ipmc_alpha" data="1.79 2.5 1.71"/>)");
  ExpectOneLineError(RunCli("bench --model " + (dir / "m.xml").string() + " --out " +
                            (dir / "bench.csv").string()),
                     "alpha", dir);
}

}  // namespace
