// The outputs of gait and closed-loop runs: time series (CSV) and
// summaries (JSON), written whole or not at all (sim/io/files.h).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/runs/closed_loop_run.h"
#include "sim/runs/gait_run.h"

namespace ipmc {

// The files a gait or closed-loop run writes into its directory, the
// summary last: a run folder with a summary is complete.
inline constexpr const char* kRunOutputFiles[] = {"timeseries.csv", "states.csv",
                                                  "summary.json"};

// Before a run, so that nothing is simulated in vain: throws if one of
// DIR's outputs would overwrite one of `inputs` (`who` and `option` name
// the command and its option), or if DIR cannot be created and written
// (sim/io/files.h). Creates nothing.
void CheckRunOutputDirectory(const std::string& who, const std::string& option,
                             const std::string& dir, const std::vector<std::string>& inputs);

nlohmann::json SwimMetricsJson(const SwimMetrics& swim);
std::string GaitSamplesCsv(const GaitRunResult& result);
nlohmann::json GaitSummaryJson(const GaitRunResult& result);

// Writes DIR/timeseries.csv, DIR/states.csv (sim/runs/recorded_states.h)
// and DIR/summary.json; its "inputs" holds `inputs`, program_version and
// model_sha256 (of inputs.model, the model file).
void WriteGaitOutputs(const std::string& dir, const GaitRunResult& result,
                      const nlohmann::json& inputs);

std::string ClosedLoopSamplesCsv(const ClosedLoopResult& result);
nlohmann::json ClosedLoopSummaryJson(const ClosedLoopResult& result);

// What a run needs to be made again, kept in summary.json's "inputs":
//   program_version    ProgramVersion() (sim/core/data_paths.h)
//   resolved_scenario  ResolvedScenarioToml (sim/core/scenario.h): every
//                      key with its value, defaults filled in
//   model_sha256       ScenarioModelSha256 (sim/runs/closed_loop_run.h)
nlohmann::json ClosedLoopProvenance(const ScenarioConfig& scenario);

// The scenario a run's summary.json recorded (inputs.resolved_scenario), to
// run it again: the same scenario gives the same timeseries.csv and
// metrics bit for bit. Throws InputError (plugin/base/error.h) naming the
// summary and the key if it has no resolved scenario, or if the model's
// bytes no longer have the recorded SHA-256.
ScenarioConfig ScenarioOfSummary(const std::string& summary_path);

// Writes DIR/timeseries.csv, DIR/states.csv and DIR/summary.json of a
// closed-loop run; summary.json's "inputs" holds `inputs` and
// ClosedLoopProvenance(scenario).
void WriteClosedLoopOutputs(const std::string& dir, const ClosedLoopResult& result,
                            const ScenarioConfig& scenario, const nlohmann::json& inputs);

}  // namespace ipmc
