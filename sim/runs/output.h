// The outputs of gait and closed-loop runs: time series (CSV) and
// summaries (JSON), written whole or not at all (sim/io/files.h).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/io/csv.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/runs/gait_run.h"

namespace ipmc {

// The files a gait or closed-loop run writes into its directory, the
// summary last: a run folder with a summary is complete.
inline constexpr const char* kRunOutputFiles[] = {"timeseries.csv", "states.csv",
                                                  "summary.json"};
// A closed-loop run also writes the model exactly as it stepped it
// (ScenarioModelXml): attached with ipmc::Attach it steps as the run did.
inline constexpr char kRunModelFile[] = "model.xml";
// Written besides them on request (RunFileFormats): the whole run in one
// file, for MATLAB/Octave and for HDF5 readers (RunResultTree).
inline constexpr char kRunMatFile[] = "run.mat";
inline constexpr char kRunHdf5File[] = "run.h5";
// The name of the struct variable in run.mat.
inline constexpr char kRunMatVariable[] = "run";

struct RunFileFormats {
  bool mat = false;   // run.mat
  bool hdf5 = false;  // run.h5
};
// The file formats a run writes, by name: "csv" (the CSV and JSON files,
// always written), "mat", "h5" (or "hdf5"); each entry may also be a
// comma-separated list. Throws FieldError naming the field "format" and
// the allowed names.
RunFileFormats ParseRunFileFormats(const std::vector<std::string>& names);

// Before a run, so that nothing is simulated in vain: throws if one of
// DIR's outputs would overwrite one of `inputs` (`who` and `option` name
// the command and its option), or if DIR cannot be created and written
// (sim/io/files.h). Creates nothing.
void CheckRunOutputDirectory(const std::string& who, const std::string& option,
                             const std::string& dir, const std::vector<std::string>& inputs);

// A run as one tree for sim/io/result_files.h, in one unit system (mm,
// s, rad, V; the time series' and summary's): the struct
//   timeseries  timeseries.csv, a column vector per column
//   states      states.csv, a column per coordinate; slides in mm
//               (`<joint>_mm`, the CSV's `<joint>_m` times 1000)
//   cycles      summary.json's per_cycle table, a column per field
//   links       summary.json's links table (closed-loop runs)
//   summary     every other field of summary.json, with its inputs
// Throws InputError if a CSV text does not parse (it is the program's own).
nlohmann::ordered_json RunResultTree(const std::string& samples_csv, const std::string& states_csv,
                                     const nlohmann::json& summary);

// The body's pose after its time, by the names of its time-series columns
// (com_x_mm, com_y_mm, head_x_mm, head_y_mm, yaw_rad; sim/io/columns.h).
std::vector<std::pair<const char*, double>> BodyPoseValues(const BodyPose& pose);

nlohmann::json SwimMetricsJson(const SwimMetrics& swim);
// A gait run's timeseries.csv by columns: time_s and the body's pose,
// q_ref<j>_rad and q<j>_rad per joint, tip<k>_x_mm and tip<k>_y_mm.
NamedColumns GaitSeriesColumns(const GaitRunResult& result);
std::string GaitSamplesCsv(const GaitRunResult& result);
nlohmann::json GaitSummaryJson(const GaitRunResult& result);

// Writes DIR/timeseries.csv, DIR/states.csv (sim/runs/recorded_states.h)
// and DIR/summary.json; its "inputs" holds `inputs`, program_version and
// model_sha256 (of inputs.model, the model file).
void WriteGaitOutputs(const std::string& dir, const GaitRunResult& result,
                      const nlohmann::json& inputs, const RunFileFormats& formats = {});

// Which cycles a run's metrics are over, and why: "cycles 2-3 (the cycles
// after the start ramp; ...)", "cycles 2-3 (metrics.from_cycle = 2)", or
// the start-up included when no cycle follows the ramp. summary.json's
// metrics_cycles and the printed summary.
std::string MetricCyclesText(const ClosedLoopResult& result);

// The start-up: the cycles before the metric cycles, which the means
// leave out (none when the metrics start at cycle 1), reported apart.
struct StartupCycles {
  int cycles = 0;
  double com_along_mm = 0.0;      // the centre of mass's swim over them
  double actuator_power_W = 0.0;  // the actuators' mean power over them
  double actuator_work_J = 0.0;
};
StartupCycles StartupOf(const ClosedLoopResult& result);

// A closed-loop run's timeseries.csv by columns, the one source of the
// CSV (ClosedLoopSamplesCsv; run.mat and run.h5 read it back) and of the
// Python module's arrays: time_s and the body's pose, reference<q>_mm,
// measured<q>_mm and voltage<q>_V per link, tip<k>_x_mm and tip<k>_y_mm.
NamedColumns ClosedLoopSeriesColumns(const ClosedLoopResult& result);
std::string ClosedLoopSamplesCsv(const ClosedLoopResult& result);
// summary.json's results: the swim and energy tables and means, the links,
// metrics_from_cycle and metrics_cycles (MetricCyclesText), startup
// (StartupOf, when the metrics leave cycles out), warnings (every line,
// ClosedLoopWarningLines) and warning_checks (each check of
// sim/runs/run_warnings.h by its column name: true where the run failed it).
nlohmann::json ClosedLoopSummaryJson(const ClosedLoopResult& result);

// What a run needs to be made again, kept in summary.json's "inputs":
//   program_version    ProgramVersion() (sim/core/data_paths.h)
//   resolved_scenario  ResolvedScenarioToml (sim/core/scenario.h): every
//                      key with its value, defaults filled in
//   model_sha256       ScenarioModelSha256 (sim/core/scenario_simulation.h)
nlohmann::json ClosedLoopProvenance(const ScenarioConfig& scenario);

// The scenario a run's summary.json recorded (inputs.resolved_scenario), to
// run it again: the same scenario gives the same timeseries.csv and
// metrics bit for bit. Throws InputError (sim/base/error.h) naming the
// summary and the key if it has no resolved scenario, or if the model's
// bytes no longer have the recorded SHA-256.
ScenarioConfig ScenarioOfSummary(const std::string& summary_path);

// The model file of a gait run's summary.json (its "inputs", inputs.model),
// checked as ScenarioOfSummary checks a closed-loop run's: throws
// InputError naming the summary and the key if there is none, or if the
// file no longer has the SHA-256 the run recorded (inputs.model_sha256).
std::string ModelOfGaitSummary(const std::string& summary_path, const nlohmann::json& inputs);

// Writes DIR/timeseries.csv, DIR/states.csv, DIR/model.xml and
// DIR/summary.json of a closed-loop run, and run.mat / run.h5 as `formats` asks, all together or
// none; summary.json's "inputs" holds `inputs` and
// ClosedLoopProvenance(scenario).
void WriteClosedLoopOutputs(const std::string& dir, const ClosedLoopResult& result,
                            const ScenarioConfig& scenario, const nlohmann::json& inputs,
                            const RunFileFormats& formats = {});

}  // namespace ipmc
