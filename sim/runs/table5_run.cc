#include "sim/runs/table5_run.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/base/error.h"
#include "sim/io/files.h"
#include "sim/base/numbers.h"
#include "controllers/fractional_integrator.h"
#include "controllers/pid.h"
#include "ipmc_swim/ipmc_swim.h"
#include "sim/core/scenario_simulation.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/core/fan_out.h"
#include "sim/runs/output.h"
#include "sim/core/data_paths.h"
#include "sim/core/simulation.h"
#include "sim/core/waveform.h"

namespace ipmc {
namespace {

constexpr char kCommand[] = "table5";
constexpr char kMultibody[] = "multibody";
constexpr char kTransferFunction[] = "transfer-function";
constexpr char kIae[] = "IAE";
constexpr char kItae[] = "ITAE";
constexpr char kFractionalLabel[] = "C_I";
constexpr char kPidLabel[] = "PID";
// Links whose length differs from the paper geometry's by more than this
// [mm] cannot use the paper's projection of the wave.
constexpr double kLengthTolerance_mm = 1e-6;

std::vector<TrackingIndices> IndicesOf(const ClosedLoopResult& result) {
  std::vector<TrackingIndices> indices;
  for (const LinkTracking& link : result.links) indices.push_back(link);
  return indices;
}

// The link plants of the scenario's model, as its actuators hold them
// (plant assignment and length scaling applied), for the
// transfer-function loop; the model's links must be the paper's, whose
// projection of the wave PaperLinkGeometry() gives.
std::vector<IpmcLinkParams> ModelLinkPlants(const ScenarioConfig& scenario) {
  if (scenario.model.Generated()) {
    throw std::runtime_error(scenario.source + ": the " + std::string(kTransferFunction) +
                             " loop needs a model file, not a generated flagellum");
  }
  // The model with the scenario's plants (ScenarioModelXml).
  const std::unique_ptr<Simulation> sim = LoadScenarioSimulation(scenario);
  const mjData* d = sim->data();
  if (!IsAttached(d) || LinkCount(d) == 0) {
    throw std::runtime_error(scenario.model.path + ": the model has no IPMC actuators");
  }
  const LinkGeometry paper = PaperLinkGeometry();
  bool paper_links = static_cast<std::size_t>(LinkCount(d)) == paper.length_mm.size();
  for (int q = 0; paper_links && q < LinkCount(d); ++q) {
    paper_links = std::abs(LinkLength_m(d, q) * 1e3 - paper.length_mm[q]) <= kLengthTolerance_mm;
  }
  if (!paper_links) {
    throw std::runtime_error(scenario.model.path + ": the " + std::string(kTransferFunction) +
                             " loop needs the paper's three 10 mm links");
  }
  return AttachedLinkPlants(d);
}

// Every link's plant P_q(s) alone in its sampled loop: at t_k = k T the
// controller takes e_k = r_q(t_k) - y_q(t_k) and holds its voltage over
// the sample, over which the plant advances exactly (zero-order hold);
// IAE and ITAE by the rectangle rule, as in the multibody run.
std::vector<TrackingIndices> RunTransferFunctionLoop(const ScenarioConfig& scenario) {
  const std::vector<IpmcLinkParams> plants = ModelLinkPlants(scenario);
  const LinkGeometry geometry = PaperLinkGeometry();
  const double sample_period_s = 1.0 / scenario.controller.sample_rate_Hz;
  const double period_s = 1.0 / std::abs(scenario.waveform.frequency_Hz);
  const double ramp_s = scenario.waveform.start_ramp_cycles * period_s;
  const long samples = std::lround(scenario.run.cycles * period_s / sample_period_s);

  struct Loop {
    HeldPlant plant;
    LinkController controller;
  };
  std::vector<Loop> loops;
  CheckLinkGains(scenario, static_cast<int>(plants.size()));
  for (size_t q = 0; q < plants.size(); ++q) {
    loops.push_back({HeldPlant(LinkStateSpace(plants[q]), sample_period_s),
                     LinkController(scenario, static_cast<int>(q))});
  }
  std::vector<TrackingIndices> indices(loops.size());
  for (long k = 0; k < samples; ++k) {
    const double t_s = static_cast<double>(k) * sample_period_s;
    const DiscreteWave wave = DiscretiseWave(scenario.waveform, geometry, t_s);
    const double ramp = StartRamp(t_s, ramp_s);
    for (std::size_t q = 0; q < loops.size(); ++q) {
      Loop& loop = loops[q];
      const double error_mm = ramp * wave.relative_deflection_mm[q] - loop.plant.Output();
      indices[q].Add(t_s, error_mm, sample_period_s);
      loop.plant.Hold(loop.controller.Update(error_mm));
      loop.plant.Advance();
    }
  }
  return indices;
}

std::vector<TrackingIndices> RunController(const ScenarioConfig& scenario, Table5Loop loop) {
  if (loop == Table5Loop::kTransferFunction) return RunTransferFunctionLoop(scenario);
  return IndicesOf(SimulateScenario(scenario));
}

}  // namespace

double RelativeError(double here, double paper) { return (here - paper) / paper; }

std::vector<Table5Row> Table5Rows(const Table5Values& here, const Table5Values& paper) {
  std::vector<Table5Row> rows;
  for (const bool iae : {true, false}) {
    const auto value = [iae](const TrackingIndices& i) { return iae ? i.iae_mm_s : i.itae_mm_s2; };
    for (std::size_t q = 0; q < here.pid.size() && q < paper.pid.size(); ++q) {
      rows.push_back({iae ? kIae : kItae, static_cast<int>(q + 1), value(here.fractional[q]),
                      value(paper.fractional[q]), value(here.pid[q]), value(paper.pid[q])});
    }
  }
  return rows;
}

const char* Table5LoopName(Table5Loop loop) {
  return loop == Table5Loop::kTransferFunction ? kTransferFunction : kMultibody;
}

void Table5Reading::Validate() const {
  if (plants != PlantAssignment::kUniform && plants != PlantAssignment::kTable2) {
    ThrowOption(kCommand, "plants", "uniform or table2", std::to_string(static_cast<int>(plants)));
  }
  if (cycles < 1 || cycles > kMaxTable5Cycles) {
    ThrowOption(kCommand, "cycles", "in [1, " + std::to_string(kMaxTable5Cycles) + "]",
                std::to_string(cycles));
  }
  if (!std::isfinite(start_ramp_cycles) || start_ramp_cycles < 0 ||
      start_ramp_cycles > cycles) {
    ThrowOption(kCommand, "start_ramp_cycles", "in [0, cycles] = [0, " + std::to_string(cycles) + "]",
                FormatDouble(start_ramp_cycles));
  }
  if (loop != Table5Loop::kMultibody && loop != Table5Loop::kTransferFunction) {
    ThrowOption(kCommand, "loop", "multibody or transfer-function",
                std::to_string(static_cast<int>(loop)));
  }
}

Table5Values PaperTable5() {
  // Table 5 of the paper: IAE [mm s] and ITAE [mm s^2] per link.
  Table5Values paper;
  paper.fractional = {{4.67, 434.90}, {13.87, 1283.50}, {18.04, 1861.70}};
  paper.pid = {{0.68, 42.0}, {2.28, 140.75}, {3.97, 269.74}};
  return paper;
}

std::string PaperScenarioPath() { return ScenariosDir() + "/paper.toml"; }

ScenarioConfig Table5Scenario(const ScenarioConfig& setting, ControllerKind controller,
                              const Table5Reading& reading) {
  ScenarioConfig scenario = setting;
  scenario.model.plants = reading.plants;
  scenario.run.cycles = reading.cycles;
  scenario.waveform.start_ramp_cycles = reading.start_ramp_cycles;
  scenario.metrics.from_cycle = 1;  // Table 5's indices: the whole run, start-up included
  scenario.controller.kind = controller;
  scenario.controller.pid.clamp_enabled = false;
  FractionalIntegrator::Config eq15;
  eq15.realisation = FractionalRealisation::kEq15;
  eq15.sample_period_s = setting.controller.pid.sample_period_s;
  eq15.clamp_enabled = false;
  scenario.controller.fractional = eq15;
  scenario.output.dir.clear();
  scenario.output.samples_per_cycle = 1;  // the indices are all this table needs
  return scenario;
}

Table5Values RunTable5(const ScenarioConfig& setting, const Table5Reading& reading, int jobs) {
  reading.Validate();
  if (jobs != 1 && jobs != 2) ThrowOption(kCommand, "jobs", "1 or 2", std::to_string(jobs));
  const ScenarioConfig fractional = Table5Scenario(setting, ControllerKind::kFractional, reading);
  const ScenarioConfig pid = Table5Scenario(setting, ControllerKind::kPid, reading);
  Table5Values values;
  FanOut(2, jobs, [&](std::size_t run) {
    if (run == 0) {
      values.fractional = RunController(fractional, reading.loop);
    } else {
      values.pid = RunController(pid, reading.loop);
    }
  });
  return values;
}

std::string Table5Csv(const Table5Values& here, const Table5Values& paper) {
  CsvWriter csv;
  csv.Row({columns::kIndex, columns::kLink, columns::kController, columns::kHere, columns::kPaper,
           columns::kRelativeError});
  for (const Table5Row& row : Table5Rows(here, paper)) {
    for (const bool is_pid : {false, true}) {
      const double value = is_pid ? row.pid_here : row.fractional_here;
      const double printed = is_pid ? row.pid_paper : row.fractional_paper;
      csv.Add(row.index).AddInteger(row.link).Add(is_pid ? kPidLabel : kFractionalLabel);
      csv.Add(value).Add(printed).Add(RelativeError(value, printed)).EndRow();
    }
  }
  return csv.Text();
}

nlohmann::json Table5Json(const Table5Values& here, const Table5Values& paper,
                          const Table5Reading& reading) {
  nlohmann::json rows = nlohmann::json::array();
  for (const Table5Row& row : Table5Rows(here, paper)) {
    for (const bool is_pid : {false, true}) {
      const double value = is_pid ? row.pid_here : row.fractional_here;
      const double printed = is_pid ? row.pid_paper : row.fractional_paper;
      rows.push_back({{"index", row.index},
                      {"link", row.link},
                      {"controller", is_pid ? kPidLabel : kFractionalLabel},
                      {"here", value},
                      {"paper", printed},
                      {"relative_error", RelativeError(value, printed)}});
    }
  }
  return {{"reading",
           {{"plants", PlantAssignmentName(reading.plants)},
            {"cycles", reading.cycles},
            {"start_ramp_cycles", reading.start_ramp_cycles},
            {"loop", Table5LoopName(reading.loop)},
            {"clamp", false},
            {"fractional_controller", "eq15"},
            {"pid_controller", "eq12"}}},
          {"units", {{"IAE", "mm s"}, {"ITAE", "mm s^2"}}},
          {"rows", rows}};
}

namespace {

OptionTable<Table5Command> MakeTable5Options() {
  OptionTable<Table5Command> table(
      kCommand,
      "Table 5: IAE and ITAE per link, C_I (eq. 15) and PID (eq. 12), beside the paper");
  OptionInfo plants{"plants", "", "", "uniform (every link eq. 7's plant) | table2 (Table 2's row "
                                      "per link)"};
  plants.choices = {"uniform", "table2"};
  table.Add<std::string>(plants, [](Table5Command& c) -> std::string& { return c.plants; });
  table.Add<int>({"cycles", "", "in [1, " + std::to_string(kMaxTable5Cycles) + "]",
                  "Horizon in wave periods (default: the scenario's)"},
                 [](Table5Command& c) -> int& { return c.cycles; });
  table.Add<double>({"start_ramp_cycles", "", "in [0, cycles]",
                     "References' fade-in in wave periods; 0: a step start (default: the "
                     "scenario's)"},
                    [](Table5Command& c) -> double& { return c.start_ramp_cycles; });
  OptionInfo loop{"loop", "", "",
                  "multibody (the MuJoCo run) | transfer-function (each link's plant alone)"};
  loop.choices = {kMultibody, kTransferFunction};
  table.Add<std::string>(loop, [](Table5Command& c) -> std::string& { return c.loop; });
  table.Add<int>({"jobs", "", "1 or 2", "Threads: 1, or 2 (one per controller)"},
                 [](Table5Command& c) -> int& { return c.jobs; });
  OptionInfo out{"out", "", "a folder", "Folder for table5.csv and table5.json"};
  out.aliases = {"o"};
  table.AddPath(out, [](Table5Command& c) -> std::string& { return c.out; });
  return table;
}

}  // namespace

const OptionTable<Table5Command>& Table5Options() {
  static const OptionTable<Table5Command> table = MakeTable5Options();
  return table;
}

Table5Outcome RunTable5Command(const Table5Command& command,
                               const std::function<bool(const std::string& field)>& given) {
  Table5Outcome outcome;
  outcome.setting = LoadScenario(PaperScenarioPath());
  const std::optional<PlantAssignment> plants = ParsePlantAssignment(command.plants);
  if (!plants) ThrowOption(kCommand, "plants", "uniform or table2", "'" + command.plants + "'");
  if (command.loop != kMultibody && command.loop != kTransferFunction) {
    ThrowOption(kCommand, "loop", "multibody or transfer-function", "'" + command.loop + "'");
  }
  Table5Reading& reading = outcome.reading;
  reading.plants = *plants;
  reading.cycles = given && given("cycles") ? command.cycles : outcome.setting.run.cycles;
  reading.start_ramp_cycles = given && given("start_ramp_cycles")
                                  ? command.start_ramp_cycles
                                  : outcome.setting.waveform.start_ramp_cycles;
  reading.loop = command.loop == kTransferFunction ? Table5Loop::kTransferFunction
                                                   : Table5Loop::kMultibody;
  outcome.here = RunTable5(outcome.setting, reading, command.jobs);  // validates first
  outcome.paper = PaperTable5();
  if (!command.out.empty()) {
    const std::string csv = Table5Csv(outcome.here, outcome.paper);
    const std::string json = Table5Json(outcome.here, outcome.paper, reading).dump(2) + "\n";
    EnsureDirectory(command.out);
    const std::filesystem::path dir(command.out);
    WriteFilesTogether({{(dir / "table5.csv").string(), csv},
                        {(dir / "table5.json").string(), json}});
  }
  return outcome;
}

}  // namespace ipmc
