#include "sim/cli/table5_command.h"

#include "sim/cli/command.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "plugin/base/error.h"
#include "sim/io/files.h"
#include "plugin/base/numbers.h"
#include "controllers/fractional_integrator.h"
#include "controllers/pid.h"
#include "plugin/coupling.h"
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
  for (const LinkTracking& link : result.links) indices.push_back({link.iae_mm_s, link.itae_mm_s2});
  return indices;
}

// The link plants of the scenario's model, as its actuators hold them
// (plant assignment and length scaling applied), for the
// transfer-function loop; the model's links must be the paper's, whose
// projection of the wave PaperLinkGeometry() gives.
std::vector<IpmcLinkParams> ModelLinkPlants(const ScenarioConfig& scenario) {
  if (scenario.GeneratesModel()) {
    throw std::runtime_error(scenario.source + ": the " + std::string(kTransferFunction) +
                             " loop needs a model file, not a generated flagellum");
  }
  IpmcActuatorsOverrides overrides;
  overrides.plants = scenario.plants;
  const Simulation sim(LoadModelFile(scenario.model_path), scenario.model_path, overrides);
  const CouplingContext* coupling = FindCoupling(sim.data());
  if (coupling == nullptr || !coupling->actuators) {
    throw std::runtime_error(scenario.model_path + ": the model has no IPMC actuators");
  }
  const LinkGeometry paper = PaperLinkGeometry();
  const std::vector<double> lengths_m = coupling->actuators->LinkLengths_m();
  bool paper_links = lengths_m.size() == paper.length_mm.size();
  for (std::size_t q = 0; paper_links && q < lengths_m.size(); ++q) {
    paper_links = std::abs(lengths_m[q] * 1e3 - paper.length_mm[q]) <= kLengthTolerance_mm;
  }
  if (!paper_links) {
    throw std::runtime_error(scenario.model_path + ": the " + std::string(kTransferFunction) +
                             " loop needs the paper's three 10 mm links");
  }
  return coupling->actuators->link_params();
}

// Every link's plant P_q(s) alone in its sampled loop: at t_k = k T the
// controller takes e_k = r_q(t_k) - y_q(t_k) and holds its voltage over
// the sample, over which the plant advances exactly (zero-order hold);
// IAE and ITAE by the rectangle rule, as in the multibody run.
std::vector<TrackingIndices> RunTransferFunctionLoop(const ScenarioConfig& scenario) {
  const std::vector<IpmcLinkParams> plants = ModelLinkPlants(scenario);
  const LinkGeometry geometry = PaperLinkGeometry();
  const double sample_period_s = 1.0 / scenario.sample_rate_Hz;
  const double period_s = 1.0 / std::abs(scenario.waveform.frequency_Hz);
  const double ramp_s = scenario.start_ramp_cycles * period_s;
  const long samples = std::lround(scenario.cycles * period_s / sample_period_s);

  struct Loop {
    DiscreteStateSpace plant;
    Eigen::VectorXd state;
    LinkController controller;
    double voltage_V = 0.0;
  };
  std::vector<Loop> loops;
  for (const IpmcLinkParams& params : plants) {
    const DiscreteStateSpace plant =
        DiscretizeZeroOrderHold(LinkStateSpace(params), sample_period_s);
    loops.push_back({plant, Eigen::VectorXd::Zero(plant.a.rows()), LinkController(scenario)});
  }
  std::vector<TrackingIndices> indices(loops.size());
  Eigen::VectorXd next;
  for (long k = 0; k < samples; ++k) {
    const double t_s = static_cast<double>(k) * sample_period_s;
    const DiscreteWave wave = DiscretiseWave(scenario.waveform, geometry, t_s);
    const double ramp = StartRamp(t_s, ramp_s);
    for (std::size_t q = 0; q < loops.size(); ++q) {
      Loop& loop = loops[q];
      const double output_mm =
          (loop.plant.c * loop.state)(0, 0) + loop.plant.d(0, 0) * loop.voltage_V;
      const double error_mm = ramp * wave.relative_deflection_mm[q] - output_mm;
      indices[q].iae_mm_s += std::abs(error_mm) * sample_period_s;
      indices[q].itae_mm_s2 += t_s * std::abs(error_mm) * sample_period_s;
      loop.voltage_V = loop.controller.Update(error_mm);
      next.noalias() = loop.plant.a * loop.state;
      next += loop.plant.b.col(0) * loop.voltage_V;
      loop.state.swap(next);
    }
  }
  return indices;
}

std::vector<TrackingIndices> RunController(const ScenarioConfig& scenario, Table5Loop loop) {
  if (loop == Table5Loop::kTransferFunction) return RunTransferFunctionLoop(scenario);
  return IndicesOf(RunScenario(scenario));
}

double RelativeError(double here, double paper) { return (here - paper) / paper; }

// Rows of the table in print order: index (IAE, ITAE), then link.
struct Row {
  const char* index;
  int link;
  double fractional_here, fractional_paper, pid_here, pid_paper;
};

std::vector<Row> Rows(const Table5Values& here, const Table5Values& paper) {
  std::vector<Row> rows;
  for (const bool iae : {true, false}) {
    const auto value = [iae](const TrackingIndices& i) { return iae ? i.iae_mm_s : i.itae_mm_s2; };
    for (std::size_t q = 0; q < here.pid.size() && q < paper.pid.size(); ++q) {
      rows.push_back({iae ? kIae : kItae, static_cast<int>(q + 1), value(here.fractional[q]),
                      value(paper.fractional[q]), value(here.pid[q]), value(paper.pid[q])});
    }
  }
  return rows;
}

std::string StartDescription(const Table5Reading& reading) {
  if (reading.start_ramp_cycles == 0.0) {
    return "references start at their t = 0 values (a step)";
  }
  return "references faded in over " + FormatDouble(reading.start_ramp_cycles, 6) + " cycles";
}

std::string LoopDescription(Table5Loop loop) {
  return loop == Table5Loop::kMultibody
             ? "multibody (the MuJoCo run of `run`)"
             : "transfer functions (each link's plant alone, no body)";
}

void PrintTable(const Table5Values& here, const Table5Values& paper,
                const Table5Reading& reading, const ScenarioConfig& setting) {
  const double period_s = 1.0 / std::abs(setting.waveform.frequency_Hz);
  std::printf("Table 5 (paper, section 5.3): tracking of each link's relative tip deflection\n");
  const std::string scenario = std::filesystem::path(setting.source).filename().string();
  std::printf("  setting scenarios/%s; linear loop (no clamp); plants %s; loop %s\n",
              scenario.c_str(), PlantAssignmentName(reading.plants),
              LoopDescription(reading.loop).c_str());
  std::printf("  horizon %d cycles (%g s); %s\n", reading.cycles, reading.cycles * period_s,
              StartDescription(reading).c_str());
  std::printf("  C_I: eq. 15 as printed; PID: eq. 12 (%g + %g/s + %g s); sampled at %g Hz\n",
              setting.pid.kp, setting.pid.ki, setting.pid.kd, setting.sample_rate_Hz);
  std::printf("%-5s %4s %12s %10s %9s %12s %10s %9s\n", "index", "link", "C_I_here", "C_I_paper",
              "C_I_err_%", "PID_here", "PID_paper", "PID_err_%");
  for (const Row& row : Rows(here, paper)) {
    std::printf("%-5s %4d %12.6g %10.6g %+9.1f %12.6g %10.6g %+9.1f\n", row.index, row.link,
                row.fractional_here, row.fractional_paper,
                100.0 * RelativeError(row.fractional_here, row.fractional_paper), row.pid_here,
                row.pid_paper, 100.0 * RelativeError(row.pid_here, row.pid_paper));
  }
  std::printf("IAE = int |e| dt [mm s], ITAE = int t |e| dt [mm s^2], e = r - y [mm]; "
              "err = (here - paper) / paper\n");
}

}  // namespace

const char* Table5LoopName(Table5Loop loop) {
  return loop == Table5Loop::kTransferFunction ? kTransferFunction : kMultibody;
}

void Table5Reading::Validate() const {
  if (plants != PlantAssignment::kUniform && plants != PlantAssignment::kTable2) {
    ThrowOption(kCommand, "--plants", "uniform or table2", std::to_string(static_cast<int>(plants)));
  }
  if (cycles < 1 || cycles > kMaxTable5Cycles) {
    ThrowOption(kCommand, "--cycles", "in [1, " + std::to_string(kMaxTable5Cycles) + "]",
                std::to_string(cycles));
  }
  if (!std::isfinite(start_ramp_cycles) || start_ramp_cycles < 0 ||
      start_ramp_cycles > cycles) {
    ThrowOption(kCommand, "--start-ramp-cycles", "in [0, --cycles] = [0, " + std::to_string(cycles) + "]",
                FormatDouble(start_ramp_cycles));
  }
  if (loop != Table5Loop::kMultibody && loop != Table5Loop::kTransferFunction) {
    ThrowOption(kCommand, "--loop", "multibody or transfer-function",
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
  scenario.plants = reading.plants;
  scenario.cycles = reading.cycles;
  scenario.start_ramp_cycles = reading.start_ramp_cycles;
  scenario.controller = controller;
  scenario.pid.clamp_enabled = false;
  FractionalIntegrator::Config eq15;
  eq15.realisation = FractionalRealisation::kEq15;
  eq15.sample_period_s = setting.pid.sample_period_s;
  eq15.clamp_enabled = false;
  scenario.fractional = eq15;
  scenario.output_dir.clear();
  scenario.samples_per_cycle = 1;  // the indices are all this table needs
  return scenario;
}

Table5Values RunTable5(const ScenarioConfig& setting, const Table5Reading& reading, int jobs) {
  reading.Validate();
  if (jobs != 1 && jobs != 2) ThrowOption(kCommand, "--jobs", "1 or 2", std::to_string(jobs));
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
  for (const Row& row : Rows(here, paper)) {
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
  for (const Row& row : Rows(here, paper)) {
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

void AddTable5Command(CLI::App& app, Table5Args& args) {
  CLI::App* cmd = AddCommand(
      app, kCommand, "Table 5: IAE and ITAE per link, C_I (eq. 15) and PID (eq. 12), beside the paper");
  cmd->add_option("--plants", args.plants,
                  "uniform (every link eq. 7's plant) | table2 (Table 2's row per link)")
      ->check(CLI::IsMember({"uniform", "table2"}));
  cmd->add_option("--cycles", args.cycles,
                  "Horizon in wave periods, [1, " + std::to_string(kMaxTable5Cycles) +
                      "] (default: the scenario's)");
  cmd->add_option("--start-ramp-cycles", args.start_ramp_cycles,
                  "References' fade-in in wave periods, [0, --cycles]; 0: a step start "
                  "(default: the scenario's)");
  cmd->add_option("--loop", args.loop,
                  "multibody (the MuJoCo run) | transfer-function (each link's plant alone)")
      ->check(CLI::IsMember({kMultibody, kTransferFunction}));
  cmd->add_option("--jobs", args.jobs, "Threads: 1, or 2 (one per controller)");
  cmd->add_option("-o,--out", args.out_dir, "Directory for table5.csv and table5.json");
}

int RunTable5Command(const CLI::App& app, const Table5Args& args) {
  if (!app.got_subcommand(kCommand)) return -1;
  const CLI::App& command = *app.get_subcommand(kCommand);
  const ScenarioConfig setting = LoadScenario(PaperScenarioPath());
  Table5Reading reading;
  reading.plants = *ParsePlantAssignment(args.plants);
  reading.cycles = command.count("--cycles") > 0 ? args.cycles : setting.cycles;
  reading.start_ramp_cycles = command.count("--start-ramp-cycles") > 0 ? args.start_ramp_cycles
                                                                        : setting.start_ramp_cycles;
  reading.loop = args.loop == kTransferFunction ? Table5Loop::kTransferFunction
                                                : Table5Loop::kMultibody;
  const Table5Values here = RunTable5(setting, reading, args.jobs);  // validates first
  const Table5Values paper = PaperTable5();
  if (!args.out_dir.empty()) {
    const std::string csv = Table5Csv(here, paper);
    const std::string json = Table5Json(here, paper, reading).dump(2) + "\n";
    EnsureDirectory(args.out_dir);
    const std::filesystem::path dir(args.out_dir);
    WriteFileAtomically((dir / "table5.csv").string(), csv);
    WriteFileAtomically((dir / "table5.json").string(), json);
  }
  PrintTable(here, paper, reading, setting);
  return 0;
}

}  // namespace ipmc
