// Running an optimisation: each evaluation a one-point sweep of the design
// (the sweep's point runner), journaled; the outputs at the end.
#include "sim/optimize/optimize_run.h"

#include <atomic>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <utility>

#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "renders/figures.h"
#include "sim/batch/cpu_affinity.h"
#include "sim/batch/sweep_scheduler.h"
#include "sim/core/data_paths.h"
#include "sim/core/sha256.h"
#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/io/files.h"
#include "sim/optimize/optimize_journal.h"
#include "sim/optimize/retune.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/runs/output.h"
#include "sim/runs/run_warnings.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;

constexpr char kOptimize[] = "optimize";
constexpr char kJournalName[] = "optimize.journal";
constexpr char kHistory[] = "history.csv";
constexpr char kConvergence[] = "convergence.csv";
constexpr char kConvergenceFigure[] = "convergence.png";
constexpr char kResult[] = "result.json";
constexpr char kBest[] = "best";

OptionTable<OptimizeCommand> MakeOptimizeOptions() {
  OptionTable<OptimizeCommand> table(
      kOptimize, "Optimise a scenario's design keys for a metric (an optimisation file, TOML)");
  OptionInfo file{"file", "", "a TOML file", "Optimisation file (docs/OPTIMIZE.md)"};
  file.positional = true;
  table.AddPath(file, [](OptimizeCommand& c) -> std::string& { return c.file; });
  OptionInfo out{"out", "", "a folder",
                 "Writes history.csv, convergence.csv, convergence.png, result.json and best/ "
                 "there, and records every evaluation in optimize.journal"};
  out.aliases = {"o"};
  out.required = true;
  table.AddPath(out, [](OptimizeCommand& c) -> std::string& { return c.out; });
  OptionInfo jobs{"jobs", "", ">= 1", "Starts run in parallel (the result does not depend on it)"};
  jobs.default_text = "the CPUs this process may use";
  table.Add<int>(jobs, [](OptimizeCommand& c) -> int& { return c.jobs; });
  table.Add<bool>({"resume", "", "",
                   "Go on with the journal in the output folder: evaluations it holds are not "
                   "run again"},
                  [](OptimizeCommand& c) -> bool& { return c.resume; });
  OptionInfo start{"start", "", "[0, the starts)",
                   "Run only this start (0: the initial point) and write only the journal: one "
                   "task of optimize --slurm"};
  start.default_text = "every start";
  table.Add<int>(start, [](OptimizeCommand& c) -> int& { return c.start; });
  table.AddPath({"journals", "", "a folder",
                 "Take the evaluations that FOLDER/start_K/optimize.journal records (the tasks "
                 "of optimize --slurm) instead of running them"},
                [](OptimizeCommand& c) -> std::string& { return c.journals; });
  return table;
}

// A run's cells (status, error, metrics) read back.
struct Cells {
  std::vector<std::string> cells;
  const std::vector<std::string>* columns;  // of the sweep row, without "point"
  std::optional<double> Metric(const std::string& name) const {
    for (size_t c = 0; c < columns->size(); ++c) {
      if ((*columns)[c] == name) return ParseDouble(cells[c]);
    }
    return std::nullopt;
  }
  bool ok() const { return cells[0] == columns::kStatusOk; }
  const std::string& error() const { return cells[1]; }
};

// The one-point sweep plan of a design (no swept columns).
SweepPlan DesignPlan(const OptimizeConfig& config) {
  SweepPlan plan;
  plan.source = config.source;
  plan.base_path = config.base_path;
  plan.links = config.links;
  return plan;
}

// The scenario of the design x, its controllers retuned if the file asks.
ScenarioConfig EvaluationScenario(const OptimizeConfig& config, const std::vector<DesignKey>& keys,
                                  const std::vector<double>& x) {
  const ScenarioConfig scenario = DesignScenario(config.base, keys, x);
  return config.retune_controllers ? RetunedControllers(scenario) : scenario;
}

// Runs the design x: status, error and the metrics, as a sweep's row has them.
std::vector<std::string> RunDesign(const OptimizeConfig& config, const std::vector<DesignKey>& keys,
                                   const std::vector<double>& x) {
  SweepPlan plan = DesignPlan(config);
  SweepPoint point;
  try {
    point.scenario = EvaluationScenario(config, keys, x);
  } catch (const std::exception& failure) {
    point.error = OneLine(failure.what());
  }
  plan.points.push_back(std::move(point));
  const SweepTable table = RunSweep(plan, SweepOptions());
  return std::vector<std::string>(table.rows.at(0).begin() + 1, table.rows.at(0).end());
}

std::string Fingerprint(const OptimizeConfig& config) {
  std::string identity = std::string(ProgramVersion()) + "\n" + ResolvedScenarioToml(config.base) +
                         "\n" + ScenarioModelSha256(config.base) + "\n";
  for (const DesignKey& key : config.Keys()) identity += key.name + "\n";
  if (config.retune_controllers) identity += "retune controllers\n";
  return Sha256Hex(identity).substr(0, 16);
}

DriverEvaluation Evaluation(const OptimizeConfig& config, const Cells& cells) {
  DriverEvaluation evaluation;
  evaluation.ok = cells.ok();
  evaluation.error = cells.error();
  if (!evaluation.ok) return evaluation;
  for (int check : FailedChecks(*cells.columns, cells.cells)) {
    evaluation.warnings += (evaluation.warnings.empty() ? "" : "; ") +
                           std::string(kRunWarningChecks[check].label);
  }
  std::optional<double> objective = cells.Metric(config.objective);
  for (const DesignConstraint& constraint : config.constraints) {
    const std::optional<double> value = cells.Metric(constraint.metric);
    evaluation.constraint_values.push_back(value.value_or(0.0));
    if (!value) evaluation.ok = false;
  }
  if (!objective) evaluation.ok = false;
  if (!evaluation.ok) evaluation.error = "a metric of the run is not a number";
  evaluation.objective = objective.value_or(0.0);
  return evaluation;
}

std::string Number(double value) { return FormatShortest(value); }

// history.csv and convergence.csv.
struct Tables {
  std::string history, convergence;
  std::vector<std::optional<double>> start_best;
};

Tables HistoryTables(const OptimizeConfig& config, const DriverResult& result) {
  const std::vector<DesignKey> keys = config.Keys();
  CsvWriter history, convergence;
  std::vector<std::string> header = {"index", "start", "evaluation"};
  for (const DesignKey& key : keys) header.push_back(key.name);
  header.push_back("objective");
  for (const DesignConstraint& constraint : config.constraints) header.push_back(constraint.metric);
  for (const char* name : {"feasible", "error", "best_so_far", kWarningsColumn}) {
    header.push_back(name);
  }
  history.Row(header);
  convergence.Row({"start", "evaluation", config.objective});
  Tables tables;
  long index = 0;
  for (const DriverStart& start : result.starts) {
    std::optional<double> best;
    for (const DriverRecord& record : start.records) {
      history.AddInteger(index++).AddInteger(record.start).AddInteger(record.evaluation);
      for (double value : record.x) history.Add(Number(value));
      history.Add(record.result.ok ? Number(record.result.objective) : "");
      for (size_t c = 0; c < config.constraints.size(); ++c) {
        history.Add(record.result.ok ? Number(record.result.constraint_values[c]) : "");
      }
      if (record.feasible && (!best || (config.maximize ? record.result.objective > *best
                                                        : record.result.objective < *best))) {
        best = record.result.objective;
      }
      history.Add(record.feasible ? "true" : "false").Add(record.result.error);
      history.Add(best ? Number(*best) : "").Add(record.result.warnings).EndRow();
      if (best) {
        convergence.AddInteger(record.start).AddInteger(record.evaluation).Add(Number(*best)).EndRow();
      }
    }
    tables.start_best.push_back(best);
  }
  tables.history = history.Text();
  tables.convergence = convergence.Text();
  return tables;
}

nlohmann::ordered_json Values(const std::vector<DesignKey>& keys, const std::vector<double>& x) {
  nlohmann::ordered_json values = nlohmann::ordered_json::object();
  for (size_t i = 0; i < keys.size() && i < x.size(); ++i) values[keys[i].name] = x[i];
  return values;
}

nlohmann::ordered_json ResultJson(const OptimizePlan& plan, const DriverResult& result,
                                  const Tables& tables, const std::vector<std::string>& columns,
                                  const std::optional<std::vector<std::string>>& best_cells) {
  const OptimizeConfig& config = plan.config;
  const std::vector<DesignKey> keys = config.Keys();
  nlohmann::ordered_json json;
  json["optimize"] = config.source;
  json["base"] = config.base_path;
  json["program_version"] = ProgramVersion();
  json["algorithm"] = AlgorithmName(config.algorithm);
  json["objective"] = {{"metric", config.objective},
                       {"sense", config.maximize ? "maximize" : "minimize"}};
  int evaluations = 0;
  for (const DriverStart& start : result.starts) evaluations += static_cast<int>(start.records.size());
  json["evaluations"] = evaluations;
  if (result.best) {
    const DriverStart& start = result.starts[result.best->start];
    json["converged"] = start.converged;
    json["stop_reason"] = start.stop_reason;
    nlohmann::ordered_json best;
    best["start"] = result.best->start;
    best["evaluation"] = result.best->evaluation;
    best["variables"] = Values(keys, result.best->x);
    best["objective"] = result.best->result.objective;
    nlohmann::ordered_json metrics = nlohmann::ordered_json::object();
    for (size_t c = 2; best_cells && c < columns.size(); ++c) {
      const std::optional<double> value = ParseDouble((*best_cells)[c]);
      if (value) metrics[columns[c]] = *value;
    }
    best["metrics"] = metrics;
    json["best"] = best;
  } else {
    json["converged"] = false;
    json["stop_reason"] = "no feasible design";
    json["best"] = nullptr;
  }
  nlohmann::ordered_json starts = nlohmann::ordered_json::array();
  for (size_t s = 0; s < result.starts.size(); ++s) {
    const DriverStart& start = result.starts[s];
    nlohmann::ordered_json entry;
    entry["start"] = s;
    std::vector<double> initial = start.initial;
    if (config.sum) initial.push_back(config.Problem().sum->Value(start.initial));
    entry["initial"] = Values(keys, initial);
    entry["evaluations"] = start.records.size();
    entry["stop_reason"] = start.stop_reason;
    entry["converged"] = start.converged;
    entry["best_objective"] =
        tables.start_best[s] ? nlohmann::ordered_json(*tables.start_best[s]) : nullptr;
    starts.push_back(entry);
  }
  json["starts"] = starts;
  return json;
}

std::string PathIn(const std::string& dir, const std::string& name) {
  return (fs::path(dir) / name).string();
}

}  // namespace

OptimizeCommand::OptimizeCommand() : jobs(AvailableCpus()) {}

std::string StartJournalPath(const std::string& folder, int start) {
  return PathIn(PathIn(folder, "start_" + std::to_string(start)), kJournalName);
}

const OptionTable<OptimizeCommand>& OptimizeOptionTable() {
  static const OptionTable<OptimizeCommand> table = MakeOptimizeOptions();
  return table;
}

OptimizePlan PlanOptimizeCommand(const OptimizeCommand& command) {
  if (command.file.empty()) {
    throw FieldError("optimize: needs an optimisation file", "file", "a TOML file");
  }
  if (command.out.empty()) throw FieldError("optimize: out is required", "out", "a folder");
  if (command.jobs < 1) {
    throw FieldError("optimize: jobs must be >= 1 (got " + std::to_string(command.jobs) + ")",
                     "jobs", ">= 1");
  }
  OptimizePlan plan;
  plan.out = command.out;
  plan.jobs = command.jobs;
  plan.resume = command.resume;
  plan.journal = PathIn(command.out, kJournalName);
  std::error_code error;
  if (fs::exists(command.out, error) && !fs::is_directory(command.out, error)) {
    throw FieldError("optimize: out " + command.out + " is not a folder", "out", "a folder");
  }
  if (fs::equivalent(command.out, command.file, error)) {
    throw FieldError("optimize: out would overwrite the optimisation file", "out", "a folder");
  }
  if (!command.resume && fs::exists(plan.journal, error)) {
    throw FieldError("optimize: " + plan.journal +
                         " exists (resume goes on with it; or choose another out)",
                     "resume", "resume, or an out without a journal");
  }
  plan.config = LoadOptimizeFile(command.file);
  const int starts = static_cast<int>(StartPoints(plan.config.Problem()).size());
  if (command.start != -1) {
    if (command.start < 0 || command.start >= starts) {
      throw FieldError("optimize: start must be in [0, " + std::to_string(starts) +
                           ") (the optimisation's starts; got " + std::to_string(command.start) +
                           ")",
                       "start", "[0, " + std::to_string(starts) + ")");
    }
    plan.only_start = command.start;
  }
  if (!command.journals.empty()) {
    if (!fs::is_directory(command.journals, error)) {
      throw FieldError("optimize: journals " + command.journals + " is not a folder", "journals",
                       "a folder");
    }
    for (int k = 0; k < starts; ++k) {
      plan.start_journals.push_back(StartJournalPath(command.journals, k));
    }
  }
  RequireWritableDirectory(command.out);
  return plan;
}

// The sweep-row columns an evaluation records (without the point index).
std::vector<std::string> JournalColumns(const OptimizeConfig& config) {
  std::vector<std::string> columns = SweepColumns(DesignPlan(config));
  columns.erase(columns.begin());
  return columns;
}

void CheckOptimizeJournals(const OptimizePlan& plan, const std::vector<std::string>& paths) {
  const std::string fingerprint = Fingerprint(plan.config);
  const std::vector<std::string> columns = JournalColumns(plan.config);
  for (const std::string& path : paths) ReadOptimizeJournal(path, fingerprint, columns);
  for (const std::string& path : paths) OptimizeJournal created(path, fingerprint, columns);
}

std::string OptimizeProgressLine(const OptimizePlan& plan, const OptimizeProgress& p) {
  std::string line = "evaluation " + std::to_string(p.done) + " (start " + std::to_string(p.start) +
                     ", #" + std::to_string(p.evaluation) + "):";
  const std::vector<DesignKey> keys = plan.config.Keys();
  for (size_t i = 0; i < keys.size() && i < p.x.size(); ++i) {
    line += " " + keys[i].name + " = " + FormatDouble(p.x[i], 6);
  }
  if (p.ok) {
    line += ", " + plan.config.objective + " = " + FormatDouble(p.objective, 6) +
            (p.feasible ? "" : " (infeasible)");
  } else {
    line += ", failed: " + p.error;
  }
  if (p.from_journal) line += " [journal]";
  return line;
}

OptimizeOutcome RunOptimizeCommand(const OptimizePlan& plan, const OptimizeHooks& hooks) {
  const OptimizeConfig& config = plan.config;
  const std::vector<DesignKey> keys = config.Keys();
  const std::vector<std::string> columns = JournalColumns(config);
  const DirectoryLock lock(plan.out);
  const std::string fingerprint = Fingerprint(config);
  // The start journals are read first: one that is refused leaves no
  // journal of this optimisation behind.
  JournalRecords start_records;
  for (const std::string& path : plan.start_journals) {
    const JournalRecords records = ReadOptimizeJournal(path, fingerprint, columns);
    start_records.insert(records.begin(), records.end());
  }
  OptimizeJournal journal(plan.journal, fingerprint, columns);

  DriverProblem problem = config.Problem();
  problem.only_start = plan.only_start.value_or(-1);
  std::atomic<int> runs{0};
  std::mutex progress_mutex;
  int done = 0, resumed = 0;
  std::map<int, int> start_evaluations;  // each start's evaluations so far
  const DriverEvaluate evaluate = [&](int start,
                                      const std::vector<double>& x) -> std::optional<DriverEvaluation> {
    std::optional<std::vector<std::string>> cells = journal.Find(x);
    if (!cells) {
      if (const auto it = start_records.find(HexKey(x)); it != start_records.end()) {
        cells = it->second;
        journal.Record(x, *cells);
      }
    }
    const bool from_journal = cells.has_value();
    if (!cells) {
      if (hooks.stop_requested && hooks.stop_requested()) return std::nullopt;
      if (hooks.stop_after_runs >= 0 && runs.fetch_add(1) >= hooks.stop_after_runs) return std::nullopt;
      cells = RunDesign(config, keys, x);
      journal.Record(x, *cells);
    }
    const DriverEvaluation evaluation = Evaluation(config, Cells{*cells, &columns});
    std::lock_guard<std::mutex> guard(progress_mutex);
    ++done;
    if (from_journal) ++resumed;
    if (hooks.on_evaluation) {
      OptimizeProgress progress;
      progress.done = done;
      progress.start = start;
      progress.evaluation = start_evaluations[start]++;
      progress.from_journal = from_journal;
      progress.ok = evaluation.ok;
      progress.error = evaluation.error;
      progress.objective = evaluation.objective;
      progress.x = x;
      bool feasible = evaluation.ok;
      for (size_t c = 0; c < config.constraints.size() && feasible; ++c) {
        feasible = config.constraints[c].bound.Violation(evaluation.constraint_values[c]) <= 0.0;
      }
      if (problem.sum) {
        feasible = feasible && x.back() >= problem.sum->lower && x.back() <= problem.sum->upper;
      }
      progress.feasible = feasible;
      hooks.on_evaluation(progress);
    }
    return evaluation;
  };
  const DriverResult result = RunDriver(problem, evaluate, plan.jobs);

  OptimizeOutcome outcome;
  outcome.resumed = resumed;
  outcome.evaluations = done;
  outcome.stopped = result.stopped;
  if (result.stopped) return outcome;
  if (plan.only_start) {
    outcome.single_start = true;  // its journal is the output
    return outcome;
  }

  // The best design's run outputs, from one more run.
  const Tables tables = HistoryTables(config, result);
  std::optional<std::vector<std::string>> best_cells;
  if (result.best) best_cells = journal.Find(result.best->x);
  outcome.result = ResultJson(plan, result, tables, columns, best_cells);
  WriteFilesTogether({{PathIn(plan.out, kHistory), tables.history},
                      {PathIn(plan.out, kConvergence), tables.convergence},
                      {PathIn(plan.out, kResult), outcome.result.dump(2) + "\n"}});
  if (result.best) {
    const ScenarioConfig scenario = EvaluationScenario(config, keys, result.best->x);
    const ClosedLoopResult run = SimulateScenario(scenario);
    const nlohmann::json inputs = {{"scenario", config.base_path},
                                   {"optimize", config.source},
                                   {"evaluation", result.best->evaluation},
                                   {"start", result.best->start}};
    WriteClosedLoopOutputs(PathIn(plan.out, kBest), run, scenario, inputs);
    FigureOptions figure;
    figure.x_column = "evaluation";
    figure.y_column = config.objective;
    figure.group_column = "start";
    figure.title = "Best so far against evaluation (" + std::string(AlgorithmName(config.algorithm)) +
                   "), one curve per start";
    DrawFigureOf(FigureKind::kSweep, PathIn(plan.out, kConvergence), figure,
                 PathIn(plan.out, kConvergenceFigure));
  }
  return outcome;
}

}  // namespace ipmc
