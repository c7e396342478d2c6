#include "sim/runs/converge_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "ipmc_swim/ipmc_swim.h"
#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/core/fan_out.h"
#include "sim/core/scenario_overrides.h"
#include "sim/core/scenario_simulation.h"
#include "sim/io/csv.h"
#include "sim/io/files.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/runs/output.h"
#include "sim/runs/run_warnings.h"

namespace ipmc {
namespace {

constexpr char kCommand[] = "converge";
constexpr int kMaxHalvings = 6;
constexpr int kMaxPlatesK = 16;
constexpr int kMaxCycles = 100;
constexpr int kMaxJobs = 64;

OptionTable<ConvergeCommand> MakeConvergeOptions() {
  OptionTable<ConvergeCommand> table(
      kCommand,
      "Run a scenario's gait at more segments per link, halved steps and finer plates; the "
      "converged swim and fluid power, each setting's error and cost");
  OptionInfo scenario{"scenario", "", "a TOML file", "Scenario file (TOML)"};
  scenario.positional = true;
  scenario.required = true;
  table.AddPath(scenario, [](ConvergeCommand& c) -> std::string& { return c.scenario; });
  OptionInfo out{"out", "", "a folder", "Folder for converge.csv and converge.png"};
  out.aliases = {"o"};
  table.AddPath(out, [](ConvergeCommand& c) -> std::string& { return c.out; });
  table.Add<int>({"max_segments", "", ">= 2",
                  "Finest segments_per_link of the segments study (1, 2, 4, ... up to it)"},
                 [](ConvergeCommand& c) -> int& { return c.max_segments; });
  table.Add<int>({"halvings", "", "in [1, " + std::to_string(kMaxHalvings) + "]",
                  "Times the timestep study halves the scenario's step"},
                 [](ConvergeCommand& c) -> int& { return c.halvings; });
  table.Add<int>({"max_plates_k", "", "0 or in [2, " + std::to_string(kMaxPlatesK) + "]",
                  "Finest fluid.plate_points_across of the plates study (1 to it); 0: no "
                  "plates study"},
                 [](ConvergeCommand& c) -> int& { return c.max_plates_k; });
  table.Add<int>({"cycles", "", "in [1, " + std::to_string(kMaxCycles) + "]",
                  "Wave periods of every run; the swim is the last one's"},
                 [](ConvergeCommand& c) -> int& { return c.cycles; });
  table.Add<int>({"jobs", "", "in [1, " + std::to_string(kMaxJobs) + "]", "Runs at once (threads)"},
                 [](ConvergeCommand& c) -> int& { return c.jobs; });
  return table;
}

void Validate(const ConvergeCommand& c) {
  if (c.max_segments < 2) ThrowOption(kCommand, "max_segments", ">= 2", std::to_string(c.max_segments));
  if (c.halvings < 1 || c.halvings > kMaxHalvings) {
    ThrowOption(kCommand, "halvings", "in [1, " + std::to_string(kMaxHalvings) + "]",
                std::to_string(c.halvings));
  }
  if (c.max_plates_k != 0 && (c.max_plates_k < 2 || c.max_plates_k > kMaxPlatesK)) {
    ThrowOption(kCommand, "max_plates_k", "0 or in [2, " + std::to_string(kMaxPlatesK) + "]",
                std::to_string(c.max_plates_k));
  }
  if (c.cycles < 1 || c.cycles > kMaxCycles) {
    ThrowOption(kCommand, "cycles", "in [1, " + std::to_string(kMaxCycles) + "]",
                std::to_string(c.cycles));
  }
  if (c.jobs < 1 || c.jobs > kMaxJobs) {
    ThrowOption(kCommand, "jobs", "in [1, " + std::to_string(kMaxJobs) + "]", std::to_string(c.jobs));
  }
}

// One run of a study: its settings over the scenario's.
struct PlannedRun {
  ConvergeRun run;
  std::vector<std::string> settings;  // KEY=VALUE
};

// Richardson's extrapolation of values at resolutions x (coarse to fine)
// whose error goes as x^-order: from the two finest, its uncertainty the
// distance to the extrapolation from the two before (three runs or more),
// else its own correction.
ConvergeReference Extrapolate(const std::vector<double>& x, const std::vector<double>& value,
                              double order) {
  const auto from = [&](std::size_t fine) {
    const double ratio = std::pow(x[fine] / x[fine - 1], order);
    return value[fine] + (value[fine] - value[fine - 1]) / (ratio - 1.0);
  };
  const std::size_t last = x.size() - 1;
  ConvergeReference reference;
  reference.value = from(last);
  reference.uncertainty = last >= 2 ? std::abs(reference.value - from(last - 1))
                                    : std::abs(reference.value - value[last]);
  return reference;
}

// The step's order: 1 for the inertial step (the drag explicit); for the
// Stokes step (the drag at the midpoint, second order, but the inputs held
// over the step, first order: docs/RUNS.md measures the two-link strip's
// swim first order) the observed order of the three finest runs, within
// [1, 2], or 1 with two runs.
double TimestepOrder(bool stokes, const std::vector<double>& value) {
  const std::size_t n = value.size();
  if (!stokes || n < 3) return 1.0;
  const double coarse = value[n - 2] - value[n - 3], fine = value[n - 1] - value[n - 2];
  if (fine == 0.0 || coarse / fine <= 0.0) return 1.0;
  return std::clamp(std::log2(coarse / fine), 1.0, 2.0);
}

double TimestepOf(const ScenarioConfig& scenario, bool* stokes) {
  const std::unique_ptr<Simulation> sim = LoadScenarioSimulation(scenario);
  *stokes = IsAttached(sim->data()) && StokesDynamics(sim->data());
  return sim->model()->opt.timestep;
}

}  // namespace

const OptionTable<ConvergeCommand>& ConvergeOptions() {
  static const OptionTable<ConvergeCommand> table = MakeConvergeOptions();
  return table;
}

double ConvergeError(double value, const ConvergeReference& reference) {
  return reference.value != 0.0 ? (value - reference.value) / reference.value : 0.0;
}

ConvergeOutcome RunConvergeCommand(const ConvergeCommand& command) {
  Validate(command);
  const std::string cycles = "cycles=" + std::to_string(command.cycles);
  const auto scenario_with = [&](const std::vector<std::string>& settings) {
    std::vector<ScenarioSetting> all = {SetOption(kCommand, cycles)};
    for (const std::string& setting : settings) all.push_back(SetOption(kCommand, setting));
    return ScenarioWithSettings(kCommand, command.scenario, all);
  };
  const ScenarioConfig base = scenario_with({});
  if (!command.out.empty()) CheckRunOutputDirectory(kCommand, "out", command.out, {command.scenario});
  bool stokes = false;
  const double step_s = TimestepOf(base, &stokes);

  std::vector<PlannedRun> planned;
  planned.push_back({{"scenario", "as given", 0.0}, {}});
  for (int n = 1; n <= command.max_segments; n *= 2) {
    const std::string setting = "segments_per_link=" + std::to_string(n);
    planned.push_back({{"segments", setting, static_cast<double>(n)}, {setting}});
  }
  for (int k = 0; k <= command.halvings; ++k) {
    const double h = step_s / std::pow(2.0, k);
    const std::string setting = "timestep_s=" + FormatShortest(h);
    planned.push_back({{"timestep", setting, 1.0 / h}, {setting}});
  }
  for (int k = 1; k <= command.max_plates_k; ++k) {
    const std::string setting = "fluid.plate_points_across=" + std::to_string(k);
    planned.push_back({{"plates", setting, static_cast<double>(k)},
                       {"fluid.model=\"plates\"", setting}});
  }
  const double period_s = 1.0 / std::abs(base.waveform.frequency_Hz);
  FanOut(planned.size(), command.jobs, [&](std::size_t i) {
    ConvergeRun& run = planned[i].run;
    const ScenarioConfig scenario = scenario_with(planned[i].settings);
    const auto start = std::chrono::steady_clock::now();
    const ClosedLoopResult result = SimulateScenario(scenario);
    const std::chrono::duration<double> wall = std::chrono::steady_clock::now() - start;
    run.swim_mm = result.swim.per_cycle.back().com_along;
    run.fluid_power_W = result.energy.per_cycle.back().fluid_power_W;
    run.cost_s_per_s = wall.count() / (command.cycles * period_s);
    run.warnings = ClosedLoopWarnings(result).Count();
  });

  ConvergeOutcome outcome;
  outcome.scenario = planned.front().run;
  const struct {
    const char* name;
    double order;  // 0: TimestepOrder
  } studies[] = {{"segments", 2.0}, {"timestep", 0.0}, {"plates", 1.0}};
  for (const auto& kind : studies) {
    ConvergeStudy study;
    study.name = kind.name;
    std::vector<double> x, swim, power;
    for (const PlannedRun& p : planned) {
      if (p.run.study != kind.name) continue;
      study.runs.push_back(p.run);
      x.push_back(p.run.resolution);
      swim.push_back(p.run.swim_mm);
      power.push_back(p.run.fluid_power_W);
    }
    if (study.runs.size() < 2) continue;
    study.swim = Extrapolate(x, swim, kind.order > 0.0 ? kind.order : TimestepOrder(stokes, swim));
    study.fluid_power =
        Extrapolate(x, power, kind.order > 0.0 ? kind.order : TimestepOrder(stokes, power));
    outcome.studies.push_back(study);
  }

  if (command.out.empty()) return outcome;
  CsvWriter csv;
  csv.Row({"study", "setting", "resolution", "swim_mm", "swim_error", "swim_abs_error_percent",
           "reference_swim_mm", "reference_swim_uncertainty_mm", "fluid_power_W",
           "fluid_power_error", "reference_fluid_power_W", "cost_s_per_simulated_s", "warnings"});
  for (const ConvergeStudy& study : outcome.studies) {
    std::vector<ConvergeRun> rows = study.runs;
    ConvergeRun scenario = outcome.scenario;
    scenario.study = study.name;
    scenario.setting = "the scenario's";
    rows.insert(rows.begin(), scenario);
    for (const ConvergeRun& run : rows) {
      const double swim_error = ConvergeError(run.swim_mm, study.swim);
      csv.Add(run.study).Add(run.setting).Add(run.resolution).Add(run.swim_mm).Add(swim_error);
      csv.Add(100.0 * std::abs(swim_error)).Add(study.swim.value).Add(study.swim.uncertainty);
      csv.Add(run.fluid_power_W).Add(ConvergeError(run.fluid_power_W, study.fluid_power));
      csv.Add(study.fluid_power.value).Add(run.cost_s_per_s).AddInteger(run.warnings);
      csv.EndRow();
    }
  }
  EnsureDirectory(command.out);
  outcome.table_path = (std::filesystem::path(command.out) / "converge.csv").string();
  WriteFilesTogether({{outcome.table_path, csv.Text()}});
  return outcome;
}

}  // namespace ipmc
