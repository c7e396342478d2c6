#include "sim/runs/output.h"

#include "sim/io/files.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace ipmc {

std::string GaitSamplesCsv(const GaitRunResult& result) {
  std::ostringstream csv;
  csv << std::setprecision(10);
  csv << "time_s,com_x_mm,com_y_mm,head_x_mm,head_y_mm,yaw_rad";
  const size_t joints = result.samples.empty() ? 0 : result.samples.front().q_rad.size();
  const size_t tips = result.samples.empty() ? 0 : result.samples.front().pose.tip_x_mm.size();
  for (size_t j = 0; j < joints; ++j) csv << ",q_ref" << j + 1 << "_rad,q" << j + 1 << "_rad";
  for (size_t k = 0; k < tips; ++k) csv << ",tip" << k + 1 << "_x_mm,tip" << k + 1 << "_y_mm";
  csv << "\n";
  for (const GaitSample& s : result.samples) {
    const BodyPose& p = s.pose;
    csv << p.t_s << "," << p.com_x_mm << "," << p.com_y_mm << "," << p.head_x_mm << ","
        << p.head_y_mm << "," << p.yaw_rad;
    for (size_t j = 0; j < joints; ++j) csv << "," << s.q_ref_rad[j] << "," << s.q_rad[j];
    for (size_t k = 0; k < tips; ++k) csv << "," << p.tip_x_mm[k] << "," << p.tip_y_mm[k];
    csv << "\n";
  }
  return csv.str();
}

nlohmann::json SwimMetricsJson(const SwimMetrics& swim) {
  nlohmann::json cycles = nlohmann::json::array();
  for (size_t k = 0; k < swim.per_cycle.size(); ++k) {
    const Displacement_mm& c = swim.per_cycle[k];
    cycles.push_back({{"cycle", k + 1},
                      {"com_along_mm", c.com_along},
                      {"com_across_mm", c.com_across},
                      {"head_along_mm", c.head_along},
                      {"head_across_mm", c.head_across}});
  }
  return {{"body_length_mm", swim.body_length_mm},
          {"per_cycle", cycles},
          {"mean_speed_along_mm_s", swim.mean_speed_along_mm_s},
          {"peak_lateral_tip_speed_mm_s", swim.peak_lateral_tip_speed_mm_s},
          {"reynolds_tip", swim.reynolds_tip},
          {"reynolds_swim", swim.reynolds_swim}};
}

nlohmann::json GaitSummaryJson(const GaitRunResult& result) {
  nlohmann::json summary = SwimMetricsJson(result.swim);
  summary["gait"] = result.gait;
  summary["period_s"] = result.period_s;
  summary["timestep_s"] = result.timestep_s;
  summary["max_tracking_error_rad"] = result.max_tracking_error_rad;
  summary["max_reference_rad"] = result.max_reference_rad;
  return summary;
}

void WriteGaitOutputs(const std::string& dir, const GaitRunResult& result,
                      const nlohmann::json& inputs) {
  EnsureDirectory(dir);
  nlohmann::json summary = GaitSummaryJson(result);
  summary["inputs"] = inputs;
  WriteFileAtomically(dir + "/timeseries.csv", GaitSamplesCsv(result));
  WriteFileAtomically(dir + "/states.csv", RecordedStatesCsv(result.states));
  WriteFileAtomically(dir + "/summary.json", summary.dump(2) + "\n");
}

std::string ClosedLoopSamplesCsv(const ClosedLoopResult& result) {
  std::ostringstream csv;
  csv << std::setprecision(10);
  csv << "time_s,com_x_mm,com_y_mm,head_x_mm,head_y_mm,yaw_rad";
  const size_t links = result.links.size();
  const size_t tips = result.samples.empty() ? 0 : result.samples.front().pose.tip_x_mm.size();
  for (size_t q = 1; q <= links; ++q) {
    csv << ",reference" << q << "_mm,measured" << q << "_mm,voltage" << q << "_V";
  }
  for (size_t k = 1; k <= tips; ++k) csv << ",tip" << k << "_x_mm,tip" << k << "_y_mm";
  csv << "\n";
  for (const ClosedLoopSample& s : result.samples) {
    const BodyPose& p = s.pose;
    csv << p.t_s << "," << p.com_x_mm << "," << p.com_y_mm << "," << p.head_x_mm << ","
        << p.head_y_mm << "," << p.yaw_rad;
    for (size_t q = 0; q < links; ++q) {
      csv << "," << s.reference_mm[q] << "," << s.measured_mm[q] << "," << s.voltage_V[q];
    }
    for (size_t k = 0; k < tips; ++k) csv << "," << p.tip_x_mm[k] << "," << p.tip_y_mm[k];
    csv << "\n";
  }
  return csv.str();
}

nlohmann::json ClosedLoopSummaryJson(const ClosedLoopResult& result) {
  nlohmann::json summary = SwimMetricsJson(result.swim);
  nlohmann::json links = nlohmann::json::array();
  for (size_t q = 0; q < result.links.size(); ++q) {
    const LinkTracking& t = result.links[q];
    links.push_back({{"link", q + 1},
                     {"iae_mm_s", t.iae_mm_s},
                     {"itae_mm_s2", t.itae_mm_s2},
                     {"max_abs_error_mm", t.max_abs_error_mm},
                     {"max_abs_reference_mm", t.max_abs_reference_mm},
                     {"rms_voltage_V", t.rms_voltage_V},
                     {"peak_voltage_V", t.peak_voltage_V},
                     {"saturated_fraction", t.saturated_fraction}});
  }
  summary["controller"] = result.controller;
  summary["actuation"] = result.actuation;
  summary["period_s"] = result.period_s;
  summary["timestep_s"] = result.timestep_s;
  summary["links"] = links;
  return summary;
}

void WriteClosedLoopOutputs(const std::string& dir, const ClosedLoopResult& result,
                            const nlohmann::json& inputs) {
  EnsureDirectory(dir);
  nlohmann::json summary = ClosedLoopSummaryJson(result);
  summary["inputs"] = inputs;
  WriteFileAtomically(dir + "/timeseries.csv", ClosedLoopSamplesCsv(result));
  WriteFileAtomically(dir + "/states.csv", RecordedStatesCsv(result.states));
  WriteFileAtomically(dir + "/summary.json", summary.dump(2) + "\n");
}

}  // namespace ipmc
