// Output files are written whole or not at all: each goes to a temporary
// file in the same directory and is renamed into place.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "sim/closed_loop_run.h"
#include "sim/gait_run.h"

namespace ipmc {

// Writes `content` to `path` atomically. Throws std::runtime_error naming
// the path on failure.
void WriteFileAtomically(const std::string& path, const std::string& content);

// Creates `dir` (and parents) if needed; throws naming the directory.
void EnsureDirectory(const std::string& dir);

nlohmann::json SwimMetricsJson(const SwimMetrics& swim);
std::string GaitSamplesCsv(const GaitRunResult& result);
nlohmann::json GaitSummaryJson(const GaitRunResult& result);

// Writes DIR/timeseries.csv and DIR/summary.json.
void WriteGaitOutputs(const std::string& dir, const GaitRunResult& result,
                      const nlohmann::json& inputs);

std::string ClosedLoopSamplesCsv(const ClosedLoopResult& result);
nlohmann::json ClosedLoopSummaryJson(const ClosedLoopResult& result);

// Writes DIR/timeseries.csv and DIR/summary.json of a closed-loop run.
void WriteClosedLoopOutputs(const std::string& dir, const ClosedLoopResult& result,
                            const nlohmann::json& inputs);

}  // namespace ipmc
