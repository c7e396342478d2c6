// The outputs of gait and closed-loop runs: time series (CSV) and
// summaries (JSON), written whole or not at all (sim/io/files.h).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "sim/runs/closed_loop_run.h"
#include "sim/runs/gait_run.h"

namespace ipmc {

nlohmann::json SwimMetricsJson(const SwimMetrics& swim);
std::string GaitSamplesCsv(const GaitRunResult& result);
nlohmann::json GaitSummaryJson(const GaitRunResult& result);

// Writes DIR/timeseries.csv, DIR/states.csv (sim/runs/recorded_states.h)
// and DIR/summary.json.
void WriteGaitOutputs(const std::string& dir, const GaitRunResult& result,
                      const nlohmann::json& inputs);

std::string ClosedLoopSamplesCsv(const ClosedLoopResult& result);
nlohmann::json ClosedLoopSummaryJson(const ClosedLoopResult& result);

// Writes DIR/timeseries.csv, DIR/states.csv and DIR/summary.json of a
// closed-loop run.
void WriteClosedLoopOutputs(const std::string& dir, const ClosedLoopResult& result,
                            const nlohmann::json& inputs);

}  // namespace ipmc
