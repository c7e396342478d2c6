// Table 5 of the paper (section 5.3), reproduced by sim/runs/table5_run.h:
// under the uniform plant assignment, at the command's default reading
// (scenarios/paper.toml in the linear loop, 3 cycles, references faded in
// over a quarter period, multibody run), C_I through eq. 15 and the PID
// of eq. 12. The expected values are the paper's Table 5 (PaperTable5());
// the residuals quoted are those of this simulator.
#include "sim/runs/table5_run.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/core/scenario.h"
#include "tests/cli_util.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;
using ::ipmc::testing::CommandResult;
using ::ipmc::testing::CountLines;
using ::ipmc::testing::RunCli;

double RelativeError(double here, double paper) { return (here - paper) / paper; }

// The paper's claims on the ordering of the table, for one reading.
void ExpectThePapersOrdering(const Table5Values& here) {
  for (const std::vector<TrackingIndices>* column : {&here.fractional, &here.pid}) {
    ASSERT_EQ(column->size(), 3u);
    // "the best performance is achieved in the first link ... the second
    // and third links obtain worse tracking": link 1 < link 2 < link 3.
    for (int q = 0; q + 1 < 3; ++q) {
      EXPECT_LT((*column)[q].iae_mm_s, (*column)[q + 1].iae_mm_s) << "IAE, link " << q + 1;
      EXPECT_LT((*column)[q].itae_mm_s2, (*column)[q + 1].itae_mm_s2) << "ITAE, link " << q + 1;
    }
  }
  // "the PID controller exhibits a better tracking performance": on every
  // link and both indices (measured: by 8.6-9.7x, the paper 4.5-10.4x).
  for (int q = 0; q < 3; ++q) {
    EXPECT_LT(here.pid[q].iae_mm_s, here.fractional[q].iae_mm_s) << "link " << q + 1;
    EXPECT_LT(here.pid[q].itae_mm_s2, here.fractional[q].itae_mm_s2) << "link " << q + 1;
  }
}

// One test, so the two 300 s multibody runs (about 9 s on two threads)
// serve every assertion.
TEST(Table5Test, UniformPlantsReproduceTheItaeColumnAndTheOrdering) {
  const ScenarioConfig setting = LoadScenario(PaperScenarioPath());
  const Table5Reading reading;  // the default reading
  const Table5Values here = RunTable5(setting, reading, 2);
  const Table5Values paper = PaperTable5();
  ASSERT_EQ(here.fractional.size(), 3u);
  ASSERT_EQ(here.pid.size(), 3u);

  // ITAE against Table 5 [mm s^2]: C_I 434.90 / 1283.50 / 1861.70, PID
  // 42 / 140.75 on links 1 / 2. Measured: C_I 426.48 / 1223.54 / 1724.70
  // (-1.9 / -4.7 / -7.4 %), PID 44.03 / 139.65 (+4.8 / -0.8 %). The
  // tolerance of 8 % is the one the reproduction claims; it is not ten
  // times the residual (link 3 of C_I leaves 0.6 points).
  constexpr double kItaeTolerance = 0.08;
  for (int q = 0; q < 3; ++q) {
    EXPECT_NEAR(RelativeError(here.fractional[q].itae_mm_s2, paper.fractional[q].itae_mm_s2), 0.0,
                kItaeTolerance)
        << "C_I, link " << q + 1 << ": " << here.fractional[q].itae_mm_s2;
  }
  for (int q = 0; q < 2; ++q) {
    EXPECT_NEAR(RelativeError(here.pid[q].itae_mm_s2, paper.pid[q].itae_mm_s2), 0.0,
                kItaeTolerance)
        << "PID, link " << q + 1 << ": " << here.pid[q].itae_mm_s2;
  }
  // What stays unexplained, held so that a change shows: the PID's link-3
  // ITAE (paper 269.74, measured 199.47: -26.1 %) and every IAE, which
  // comes out 1.6-3x below the paper (measured -36 to -41 % for C_I, -55 to
  // -66 % for PID). Bounds: the measured values +-5 points.
  EXPECT_NEAR(RelativeError(here.pid[2].itae_mm_s2, paper.pid[2].itae_mm_s2), -0.261, 0.05);
  for (int q = 0; q < 3; ++q) {
    EXPECT_LT(RelativeError(here.fractional[q].iae_mm_s, paper.fractional[q].iae_mm_s), -0.31);
    EXPECT_GT(RelativeError(here.fractional[q].iae_mm_s, paper.fractional[q].iae_mm_s), -0.46);
    EXPECT_LT(RelativeError(here.pid[q].iae_mm_s, paper.pid[q].iae_mm_s), -0.49);
    EXPECT_GT(RelativeError(here.pid[q].iae_mm_s, paper.pid[q].iae_mm_s), -0.72);
  }
  ExpectThePapersOrdering(here);

  // The links' plants alone (no body, drag or coupling) give the same
  // table: measured largest difference 2.5e-5 relative; tolerance 2.5e-4.
  Table5Reading transfer_functions = reading;
  transfer_functions.loop = Table5Loop::kTransferFunction;
  const Table5Values alone = RunTable5(setting, transfer_functions, 2);
  for (int q = 0; q < 3; ++q) {
    EXPECT_NEAR(alone.fractional[q].iae_mm_s / here.fractional[q].iae_mm_s, 1.0, 2.5e-4);
    EXPECT_NEAR(alone.fractional[q].itae_mm_s2 / here.fractional[q].itae_mm_s2, 1.0, 2.5e-4);
    EXPECT_NEAR(alone.pid[q].iae_mm_s / here.pid[q].iae_mm_s, 1.0, 2.5e-4);
    EXPECT_NEAR(alone.pid[q].itae_mm_s2 / here.pid[q].itae_mm_s2, 1.0, 2.5e-4);
  }
  // Two threads or one: the same numbers, bit for bit.
  const Table5Values sequential = RunTable5(setting, transfer_functions, 1);
  for (int q = 0; q < 3; ++q) {
    EXPECT_EQ(sequential.fractional[q].iae_mm_s, alone.fractional[q].iae_mm_s);
    EXPECT_EQ(sequential.fractional[q].itae_mm_s2, alone.fractional[q].itae_mm_s2);
    EXPECT_EQ(sequential.pid[q].iae_mm_s, alone.pid[q].iae_mm_s);
    EXPECT_EQ(sequential.pid[q].itae_mm_s2, alone.pid[q].itae_mm_s2);
  }
}

TEST(Table5Test, ScenariosAreTheLinearLoopWithEq15) {
  const ScenarioConfig setting = LoadScenario(PaperScenarioPath());
  Table5Reading reading;
  reading.plants = PlantAssignment::kTable2;
  reading.cycles = 2;
  reading.start_ramp_cycles = 0.0;
  const ScenarioConfig fractional = Table5Scenario(setting, ControllerKind::kFractional, reading);
  EXPECT_EQ(fractional.controller.kind, ControllerKind::kFractional);
  EXPECT_EQ(fractional.controller.fractional.realisation, FractionalRealisation::kEq15);
  EXPECT_FALSE(fractional.controller.fractional.clamp_enabled);
  EXPECT_EQ(fractional.controller.fractional.sample_period_s, 1e-3);
  EXPECT_EQ(fractional.model.plants, PlantAssignment::kTable2);
  EXPECT_EQ(fractional.run.cycles, 2);
  EXPECT_EQ(fractional.waveform.start_ramp_cycles, 0.0);
  EXPECT_TRUE(fractional.output.dir.empty());
  const ScenarioConfig pid = Table5Scenario(setting, ControllerKind::kPid, reading);
  EXPECT_EQ(pid.controller.kind, ControllerKind::kPid);
  EXPECT_FALSE(pid.controller.pid.clamp_enabled);
  EXPECT_EQ(pid.controller.pid.kp, 8.12);  // eq. 12, from paper.toml
  EXPECT_EQ(pid.controller.pid.ki, 53.36);
  EXPECT_EQ(pid.controller.pid.kd, 0.61);
}

std::string ReadText(const fs::path& path) {
  std::ifstream file(path);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

// The command's files: 12 rows (2 indices x 3 links x 2 controllers) with
// the paper's values; one cycle of the transfer-function loop keeps it
// short.
TEST(Table5CommandTest, WritesTheTableAsCsvAndJson) {
  const fs::path dir = ::ipmc::testing::FreshDir("table5_out");
  const CommandResult result =
      RunCli("table5 --loop transfer-function --cycles 1 --out " + (dir / "out").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("ITAE     3"), std::string::npos) << result.output;
  const std::string csv = ReadText(dir / "out" / "table5.csv");
  EXPECT_EQ(CountLines(csv), 13) << csv;
  EXPECT_EQ(csv.rfind("index,link,controller,here,paper,relative_error\n", 0), 0u) << csv;
  EXPECT_NE(csv.find("\nITAE,3,PID,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",269.74"), std::string::npos) << csv;
  const nlohmann::json json = nlohmann::json::parse(ReadText(dir / "out" / "table5.json"));
  EXPECT_EQ(json["reading"]["cycles"], 1);
  EXPECT_EQ(json["reading"]["loop"], "transfer-function");
  EXPECT_EQ(json["reading"]["plants"], "uniform");
  ASSERT_EQ(json["rows"].size(), 12u);
  EXPECT_EQ(json["rows"][0]["index"], "IAE");
  EXPECT_EQ(json["rows"][0]["controller"], "C_I");
  EXPECT_EQ(json["rows"][0]["paper"], 4.67);
  for (const fs::directory_entry& entry : fs::directory_iterator(dir / "out")) {
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
  }
}

void ExpectOneLineError(const std::string& args, const std::string& what) {
  const fs::path dir = ::ipmc::testing::FreshDir("table5_bad");
  const CommandResult result = RunCli("table5 " + args + " --out " + (dir / "out").string());
  EXPECT_NE(result.exit_code, 0) << args << ": " << result.output;
  EXPECT_EQ(CountLines(result.output), 1) << args << ": " << result.output;
  EXPECT_EQ(result.output.rfind("ipmc-swim: error: ", 0), 0u) << result.output;
  EXPECT_NE(result.output.find(what), std::string::npos) << args << ": " << result.output;
  EXPECT_FALSE(fs::exists(dir / "out")) << args;
}

TEST(Table5CommandTest, BadOptionsGiveOneLineAndNoFiles) {
  ExpectOneLineError("--cycles 0", "table5: --cycles must be in [1, 100], got 0");
  ExpectOneLineError("--cycles 101", "table5: --cycles must be in [1, 100], got 101");
  ExpectOneLineError("--start-ramp-cycles -0.5",
                     "table5: --start-ramp-cycles must be in [0, --cycles] = [0, 3], got -0.5");
  ExpectOneLineError("--cycles 1 --start-ramp-cycles 2",
                     "table5: --start-ramp-cycles must be in [0, --cycles] = [0, 1], got 2");
  ExpectOneLineError("--jobs 3", "table5: --jobs must be 1 or 2, got 3");
  ExpectOneLineError("--plants table3", "--plants");
  ExpectOneLineError("--loop simulink", "--loop");
  ExpectOneLineError("--cycles three", "--cycles");
}

}  // namespace
}  // namespace ipmc
