// Runs from Python: a closed-loop scenario with overrides, a sweep, the
// merge of a sweep's shards, the convergence study, a bench experiment,
// the MJCF generator and the key and option references, each the computation its ipmc-swim
// command makes, returning numbers or text instead of printing them and
// writing the command's files only when asked to.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "renders/figures.h"
#include "sim/optimize/option_reference.h"
#include "sim/batch/sweep.h"
#include "sim/batch/sweep_command.h"
#include "sim/core/keys_command.h"
#include "sim/core/generate_command.h"
#include "sim/core/resistance_command.h"
#include "sim/core/simulation.h"
#include "sim/io/files.h"
#include "sim/python/convert.h"
#include "sim/runs/bench_command.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/runs/converge_study.h"
#include "sim/runs/output.h"
#include "sim/runs/run_command.h"

namespace ipmc::python {
namespace {

// A table by columns (the library's, as its CSV holds them), one array per column.
py::dict ColumnDict(const NamedColumns& columns) {
  py::dict dict;
  for (const auto& [name, values] : columns) dict[py::str(name)] = Array(values);
  return dict;
}

// ------------------------------------------------------------------- run ---

py::dict Run(const py::object& scenario_arg, const py::dict& overrides, const py::dict& kwargs,
             const py::object& progress_callback) {
  Options options("run", kwargs);
  const RunCommand command = ReadCommandKeywords(options, RunOptions());
  ScenarioArgument argument = ReadScenarioArgument(scenario_arg, overrides, "run");
  const nlohmann::json& source = argument.inputs["scenario"];
  const std::vector<std::string> input_files =
      source.is_string() ? std::vector<std::string>{source.get<std::string>()}
                         : std::vector<std::string>{};
  // As the command line: every output is checked before the run.
  const RunPlan plan = PlanRunCommand(command, std::move(argument.scenario),
                                      std::move(argument.inputs), input_files);
  const ScenarioConfig& scenario = plan.scenario;
  const double total_s = scenario.run.cycles / std::abs(scenario.waveform.frequency_Hz);
  Progress progress(progress_callback, total_s);
  // Ctrl-C stops the run at its next recorded sample, as on the command line.
  const ClosedLoopResult result = Interruptible([&](const std::atomic<bool>& stop) {
    const SampleObserver observer = [&](const mjModel*, const mjData* d, const ClosedLoopSample&) {
      ThrowIfStopRequested(stop);
      progress.Report(d->time);
    };
    return SimulateScenario(scenario, observer, [&stop](double) { ThrowIfStopRequested(stop); });
  });
  progress.Report(total_s, true);
  WithoutGil([&] { WriteRunOutputs(plan, result); });
  py::dict dict;
  dict["timeseries"] = ColumnDict(ClosedLoopSeriesColumns(result));
  dict["summary"] = ToPython(ClosedLoopSummaryJson(result));
  return dict;
}

// ----------------------------------------------------------------- sweep ---

py::object Sweep(const py::object& path_arg, const py::dict& kwargs,
                 const py::object& progress_callback) {
  Options options("sweep", kwargs);
  SweepCommand file;
  file.sweep = PathText(path_arg, "sweep");
  const SweepCommand command = ReadCommandKeywords(options, SweepOptionTable(), file);
  // As the command line: the journal PREFIX.journal holds the output (one
  // sweep per prefix, from either front end) and resumes a stopped sweep.
  std::unique_ptr<SweepCommandRun> sweep = WithoutGil(
      [&] { return std::make_unique<SweepCommandRun>(PlanSweepCommand(command)); });
  Progress progress(progress_callback, sweep->ToRun());
  // Ctrl-C lets the running points finish (recorded in the journal) and
  // starts no other; nothing else is written.
  const SweepCommandOutcome outcome = Interruptible([&](const std::atomic<bool>& stop) {
    return sweep->Run([&](const SweepProgress& p) { progress.Report(p.done, true); },
                      [&stop] { return stop.load(); });
  });
  const SweepTable& table = outcome.table;
  return ToPython(SweepTableJson(table));
}

// ----------------------------------------------------------------- merge ---

py::object Merge(const py::object& tables_arg, const py::dict& kwargs) {
  Options options("merge", kwargs);
  MergeCommand tables;
  if (py::isinstance<py::str>(tables_arg) || !py::isinstance<py::sequence>(tables_arg)) {
    tables.tables.push_back(PathText(tables_arg, "merge(): tables"));
  } else {
    for (const py::handle table : tables_arg) {
      tables.tables.push_back(PathText(table, "merge(): tables"));
    }
  }
  const MergeCommand command = ReadCommandKeywords(options, MergeOptionTable(), tables);
  // Ctrl-C stops it before it writes, as on the command line.
  const SweepTable merged = Interruptible([&](const std::atomic<bool>& stop) {
    return RunMergeCommand(command, [&stop] { ThrowIfStopRequested(stop); });
  });
  return ToPython(SweepTableJson(merged));
}

// -------------------------------------------------------------- converge ---

py::dict ConvergeRunDict(const ConvergeRun& run, const ConvergeStudy& study) {
  py::dict dict;
  dict["setting"] = run.setting;
  dict["resolution"] = run.resolution;
  dict["swim_mm"] = run.swim_mm;
  dict["swim_error"] = ConvergeError(run.swim_mm, study.swim);
  dict["fluid_power_W"] = run.fluid_power_W;
  dict["fluid_power_error"] = ConvergeError(run.fluid_power_W, study.fluid_power);
  dict["cost_s_per_simulated_s"] = run.cost_s_per_s;
  dict["warnings"] = run.warnings;
  return dict;
}

py::list Converge(const py::object& scenario_arg, const py::dict& kwargs) {
  Options options("converge", kwargs);
  ConvergeCommand scenario;
  scenario.scenario = PathText(scenario_arg, "converge");
  const ConvergeCommand command = ReadCommandKeywords(options, ConvergeOptions(), scenario);
  // As the command line: OUT/converge.csv and its figure.
  const ConvergeOutcome outcome = WithoutGil([&] {
    ConvergeOutcome done = RunConvergeCommand(command);
    if (!done.table_path.empty()) {
      DrawConvergeFigure(done.table_path,
                         (std::filesystem::path(command.out) / "converge.png").string());
    }
    return done;
  });
  py::list studies;
  for (const ConvergeStudy& study : outcome.studies) {
    py::dict dict;
    dict["study"] = study.name;
    dict["swim_mm"] = study.swim.value;
    dict["swim_uncertainty_mm"] = study.swim.uncertainty;
    dict["fluid_power_W"] = study.fluid_power.value;
    dict["fluid_power_uncertainty_W"] = study.fluid_power.uncertainty;
    ConvergeRun as_given = outcome.scenario;
    as_given.setting = "the scenario's";
    dict["scenario"] = ConvergeRunDict(as_given, study);
    py::list runs;
    for (const ConvergeRun& run : study.runs) runs.append(ConvergeRunDict(run, study));
    dict["runs"] = runs;
    studies.append(dict);
  }
  return studies;
}

// -------------------------------------------------------------- references ---

std::string Keys(const py::dict& kwargs) {
  Options options("keys", kwargs);
  return KeysReference(ReadCommandKeywords(options, KeysOptions()));
}

std::string OptionsText(const py::dict& kwargs) {
  Options options("options", kwargs);
  return OptionsReference(ReadCommandKeywords(options, OptionsOptions()));
}

// ----------------------------------------------------------------- bench ---

py::dict Bench(const py::dict& kwargs, const py::object& progress_callback) {
  Options options("bench", kwargs);
  const BenchCommand command = ReadCommandKeywords(options, BenchOptions());
  Progress progress(progress_callback, command.bench.duration_s);
  const BenchRecord record = Interruptible([&](const std::atomic<bool>& stop) {
    return RunBenchCommand(command, [&](double t_s) {
      ThrowIfStopRequested(stop);
      progress.Report(t_s);
    });
  });
  progress.Report(command.bench.duration_s, true);
  return ColumnDict(BenchColumns(record));
}

// -------------------------------------------------------------- generate ---

std::string GenerateModel(const py::dict& kwargs) {
  Options options("generate_model", kwargs);
  return RunGenerateCommand(ReadCommandKeywords(options, GenerateOptions()));
}

// ------------------------------------------------------------ resistance ---

py::dict Resistance(const std::string& model, const py::dict& kwargs) {
  Options options("resistance", kwargs);
  ResistanceCommand command = ReadCommandKeywords(options, ResistanceOptions());
  command.model = model;
  const ResistanceOutcome outcome = RunResistanceCommand(command);
  py::list rows;
  for (int i = 0; i < 6; ++i) {
    py::list row;
    for (int j = 0; j < 6; ++j) row.append(outcome.resistance[6 * i + j]);
    rows.append(row);
  }
  py::dict result;
  result["R"] = rows;
  result["A_N_s_m"] = outcome.propulsion.a_N_s_m;
  result["B_N_s"] = outcome.propulsion.b_N_s;
  result["D_N_m_s"] = outcome.propulsion.d_N_m_s;
  return result;
}

}  // namespace

void BindRuns(py::module_& m) {
  m.def("run", &Run, py::arg("scenario"), py::arg("overrides"), py::arg("options"),
        py::arg("progress"));
  m.def("sweep", &Sweep, py::arg("sweep"), py::arg("options"), py::arg("progress"));
  m.def("merge", &Merge, py::arg("tables"), py::arg("options"));
  m.def("converge", &Converge, py::arg("scenario"), py::arg("options"));
  m.def("keys", &Keys, py::arg("options"));
  m.def("options", &OptionsText, py::arg("options"));
  m.def("bench", &Bench, py::arg("options"), py::arg("progress"));
  m.def("generate_model", &GenerateModel, py::arg("options"));
  m.def("resistance", &Resistance, py::arg("model"), py::arg("options"));
}

}  // namespace ipmc::python
