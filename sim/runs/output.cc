#include "sim/runs/output.h"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <sstream>
#include <iterator>

#include "sim/core/data_paths.h"
#include "sim/core/scenario.h"
#include "sim/core/scenario_simulation.h"
#include "sim/core/sha256.h"
#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/base/error.h"
#include "sim/io/files.h"
#include "sim/io/result_files.h"
#include "sim/runs/run_warnings.h"

namespace ipmc {
namespace {

// Time series are written at 10 significant digits.
constexpr int kSeriesDigits = 10;

// Keys of summary.json's "inputs".
constexpr char kInputs[] = "inputs";
constexpr char kProgramVersion[] = "program_version";
constexpr char kResolvedScenario[] = "resolved_scenario";
constexpr char kModelSha256[] = "model_sha256";

// Throws InputError naming the summary and inputs.model_sha256 unless the
// model (its description, `model`) still has the SHA-256 the run recorded.
void RequireRecordedModel(const std::string& summary_path, const std::string& recorded,
                          const std::string& now, const std::string& model) {
  if (now == recorded) return;
  throw InputError(InputProblem::kBadValue, {summary_path},
                   std::string(kInputs) + "." + kModelSha256,
                   "the model " + model + " has changed since the run (SHA-256 " + now +
                       ", recorded " + recorded + ")",
                   recorded);
}

std::string ModelFileSha256(const std::string& path) {
  return Sha256Hex(ReadTextFile(path, "model file"));
}

// Appends a sample's pose to the body's columns (time and BodyPoseValues,
// first in every time series) and to the tips' (last).
void AddPose(const BodyPose& pose, size_t tips, NamedColumns& body, NamedColumns& tip_columns) {
  if (body.empty()) {
    body.push_back({columns::kTime, {}});
    for (const auto& [name, value] : BodyPoseValues(pose)) body.push_back({name, {}});
    for (size_t k = 1; k <= tips; ++k) {
      tip_columns.push_back({columns::TipX(static_cast<int>(k)), {}});
      tip_columns.push_back({columns::TipY(static_cast<int>(k)), {}});
    }
  }
  size_t c = 0;
  body[c++].second.push_back(pose.t_s);
  for (const auto& [name, value] : BodyPoseValues(pose)) body[c++].second.push_back(value);
  for (size_t k = 0; k < tips; ++k) {
    tip_columns[2 * k].second.push_back(pose.tip_x_mm[k]);
    tip_columns[2 * k + 1].second.push_back(pose.tip_y_mm[k]);
  }
}

// A time series's columns: the body's, `middle` (per link or joint), the tips'.
NamedColumns SeriesColumns(NamedColumns body, NamedColumns middle, NamedColumns tips) {
  if (body.empty()) {
    body.push_back({columns::kTime, {}});
    for (const auto& [name, value] : BodyPoseValues(BodyPose{})) body.push_back({name, {}});
  }
  for (auto& column : middle) body.push_back(std::move(column));
  for (auto& column : tips) body.push_back(std::move(column));
  return body;
}

std::string RunOutputPath(const std::string& dir, int file) {
  return (std::filesystem::path(dir) / kRunOutputFiles[file]).string();
}

// A CSV text as an object of columns, each an array of its numbers.
nlohmann::ordered_json CsvColumns(const std::string& csv, const std::string& source,
                                  const std::function<void(std::string&, std::vector<double>&)>&
                                      relabel = nullptr) {
  const CsvTable table = CsvTable::Parse(csv, source);
  nlohmann::ordered_json columns = nlohmann::ordered_json::object();
  for (const std::string& column : table.columns()) {
    std::string name = column;
    std::vector<double> values = table.Numbers(column);
    if (relabel) relabel(name, values);
    columns[name] = values;
  }
  return columns;
}

bool EndsWith(const std::string& text, const std::string& end) {
  return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

// kRunOutputFiles (the summary with the inputs) and the files `formats`
// asks for, together or not at all.
// model_xml: the model as stepped (kRunModelFile), "" for none.
void WriteRunOutputs(const std::string& dir, const std::string& csv, const std::string& states_csv,
                     nlohmann::json summary, const nlohmann::json& inputs,
                     const RunFileFormats& formats, const std::string& model_xml = "") {
  EnsureDirectory(dir);
  summary[kInputs] = inputs;
  // Renamed into place in this order: the summary, which marks a complete
  // run folder, last.
  // A file of an earlier run that this one does not write goes, so the
  // folder never holds two runs' files.
  std::vector<std::pair<std::string, std::string>> files;
  std::vector<std::string> stale;
  const std::filesystem::path folder(dir);
  const std::string mat_path = (folder / kRunMatFile).string();
  const std::string hdf5_path = (folder / kRunHdf5File).string();
  if (formats.mat || formats.hdf5) {
    const nlohmann::ordered_json tree = RunResultTree(csv, states_csv, summary);
    if (formats.mat) files.emplace_back(mat_path, MatFileBytes(kRunMatVariable, tree));
    if (formats.hdf5) files.emplace_back(hdf5_path, Hdf5FileBytes(tree));
  }
  if (!formats.mat) stale.push_back(mat_path);
  if (!formats.hdf5) stale.push_back(hdf5_path);
  files.emplace_back(RunOutputPath(dir, 0), csv);
  files.emplace_back(RunOutputPath(dir, 1), states_csv);
  const std::string model_path = (folder / kRunModelFile).string();
  if (model_xml.empty()) {
    stale.push_back(model_path);
  } else {
    files.emplace_back(model_path, model_xml);
  }
  files.emplace_back(RunOutputPath(dir, 2), summary.dump(2) + "\n");
  WriteFilesTogether(files, stale);
}

}  // namespace

void CheckRunOutputDirectory(const std::string& who, const std::string& option,
                             const std::string& dir, const std::vector<std::string>& inputs) {
  for (int file = 0; file < static_cast<int>(std::size(kRunOutputFiles)); ++file) {
    RefuseOverwritingInputs(who, option, RunOutputPath(dir, file), inputs);
  }
  for (const char* file : {kRunMatFile, kRunHdf5File, kRunModelFile}) {
    RefuseOverwritingInputs(who, option, (std::filesystem::path(dir) / file).string(), inputs);
  }
  RequireWritableDirectory(dir);
}

RunFileFormats ParseRunFileFormats(const std::vector<std::string>& names) {
  RunFileFormats formats;
  for (const std::string& entry : names) {
    std::stringstream list(entry);
    for (std::string name; std::getline(list, name, ',');) {
      if (name == "mat") {
        formats.mat = true;
      } else if (name == "h5" || name == "hdf5") {
        formats.hdf5 = true;
      } else if (name != "csv") {
        throw FieldError("format must be csv, mat or h5 (hdf5), got '" + name + "'", "format",
                         "csv, mat, h5");
      }
    }
  }
  return formats;
}

nlohmann::ordered_json RunResultTree(const std::string& samples_csv, const std::string& states_csv,
                                     const nlohmann::json& summary) {
  nlohmann::ordered_json tree;
  tree["timeseries"] = CsvColumns(samples_csv, kRunOutputFiles[0]);
  // states.csv keeps MuJoCo's metres; the tree is in millimetres throughout.
  tree["states"] = CsvColumns(states_csv, kRunOutputFiles[1],
                              [](std::string& name, std::vector<double>& values) {
                                if (!EndsWith(name, "_m")) return;
                                name += "m";
                                for (double& value : values) value *= 1e3;
                              });
  nlohmann::ordered_json rest = summary;
  for (const char* table : {"per_cycle", "links"}) {
    if (!rest.contains(table)) continue;
    tree[std::string(table) == "per_cycle" ? "cycles" : table] = rest[table];
    rest.erase(table);
  }
  tree["summary"] = rest;
  return tree;
}

NamedColumns GaitSeriesColumns(const GaitRunResult& result) {
  const size_t joints = result.samples.empty() ? 0 : result.samples.front().q_rad.size();
  const size_t tips = result.samples.empty() ? 0 : result.samples.front().pose.tip_x_mm.size();
  NamedColumns body, per_joint, tip_columns;
  for (size_t j = 1; j <= joints; ++j) {
    per_joint.push_back({columns::JointReference(static_cast<int>(j)), {}});
    per_joint.push_back({columns::JointAngle(static_cast<int>(j)), {}});
  }
  for (const GaitSample& s : result.samples) {
    AddPose(s.pose, tips, body, tip_columns);
    for (size_t j = 0; j < joints; ++j) {
      per_joint[2 * j].second.push_back(s.q_ref_rad[j]);
      per_joint[2 * j + 1].second.push_back(s.q_rad[j]);
    }
  }
  return SeriesColumns(std::move(body), std::move(per_joint), std::move(tip_columns));
}

std::string GaitSamplesCsv(const GaitRunResult& result) {
  return NamedColumnsCsv(GaitSeriesColumns(result), kSeriesDigits);
}

std::vector<std::pair<const char*, double>> BodyPoseValues(const BodyPose& pose) {
  return {{columns::kComX, pose.com_x_mm},
          {columns::kComY, pose.com_y_mm},
          {columns::kHeadX, pose.head_x_mm},
          {columns::kHeadY, pose.head_y_mm},
          {columns::kYaw, pose.yaw_rad}};
}

// Whether the step resolves the swim (sim/core/step_resolution.h).
nlohmann::json StepResolutionJson(const StepResolution& step) {
  return {{"explicit_drag", step.explicit_drag},
          {"timestep_s", step.timestep_s},
          {"drag_relaxation_s", step.drag_relaxation_s},
          {"swim_error", step.swim_error},
          {"resolving_timestep_s", step.resolving_timestep_s},
          {"resolved", step.Resolved()}};
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
          {"reynolds_swim", swim.reynolds_swim},
          {"reynolds_oscillatory", swim.reynolds_oscillatory},
          {"frequency_Hz", swim.frequency_Hz},
          {"viscosity_Pa_s", swim.viscosity_Pa_s},
          {"step_resolution", StepResolutionJson(swim.step)},
          {"warnings", swim.warnings}};
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
                      const nlohmann::json& inputs, const RunFileFormats& formats) {
  nlohmann::json all = inputs;
  all[kProgramVersion] = ProgramVersion();
  if (inputs.contains("model") && inputs["model"].is_string()) {
    all[kModelSha256] = ModelFileSha256(inputs["model"].get<std::string>());
  }
  WriteRunOutputs(dir, GaitSamplesCsv(result), RecordedStatesCsv(result.states),
                  GaitSummaryJson(result), all, formats);
}

NamedColumns ClosedLoopSeriesColumns(const ClosedLoopResult& result) {
  const size_t links = result.links.size();
  const size_t tips = result.samples.empty() ? 0 : result.samples.front().pose.tip_x_mm.size();
  NamedColumns body, per_link, tip_columns;
  for (size_t q = 1; q <= links; ++q) {
    const int link = static_cast<int>(q);
    for (const std::string& name :
         {columns::Reference(link), columns::Measured(link), columns::Voltage(link)}) {
      per_link.push_back({name, {}});
    }
  }
  for (const ClosedLoopSample& s : result.samples) {
    AddPose(s.pose, tips, body, tip_columns);
    for (size_t q = 0; q < links; ++q) {
      per_link[3 * q].second.push_back(s.reference_mm[q]);
      per_link[3 * q + 1].second.push_back(s.measured_mm[q]);
      per_link[3 * q + 2].second.push_back(s.voltage_V[q]);
    }
  }
  return SeriesColumns(std::move(body), std::move(per_link), std::move(tip_columns));
}

std::string ClosedLoopSamplesCsv(const ClosedLoopResult& result) {
  return NamedColumnsCsv(ClosedLoopSeriesColumns(result), kSeriesDigits);
}

StartupCycles StartupOf(const ClosedLoopResult& result) {
  StartupCycles startup;
  startup.cycles = std::max(0, result.swim.from_cycle - 1);
  for (int k = 0; k < startup.cycles; ++k) {
    if (static_cast<size_t>(k) < result.swim.per_cycle.size()) {
      startup.com_along_mm += result.swim.per_cycle[k].com_along;
    }
    if (static_cast<size_t>(k) < result.energy.per_cycle.size()) {
      const double power_W = result.energy.per_cycle[k].actuator_power_W_total;
      startup.actuator_work_J += power_W * result.period_s;
    }
  }
  const double time_s = startup.cycles * result.period_s;
  startup.actuator_power_W = time_s > 0.0 ? startup.actuator_work_J / time_s : 0.0;
  return startup;
}

std::string MetricCyclesText(const ClosedLoopResult& result) {
  const int from = result.swim.from_cycle;
  const std::string cycles = "cycles " + std::to_string(from) + "-" +
                             std::to_string(result.swim.per_cycle.size());
  if (result.from_cycle_given) {
    return cycles + " (metrics.from_cycle = " + std::to_string(from) + ")";
  }
  if (result.startup_included) {
    return cycles + " (no cycle follows the start ramp: the start-up is included; run more "
                    "cycles for steady values)";
  }
  return cycles + " (the cycles after the start ramp; metrics.from_cycle = 1 takes the whole run)";
}

namespace {

nlohmann::json StartupJson(const ClosedLoopResult& result) {
  const StartupCycles startup = StartupOf(result);
  return {{"cycles", startup.cycles},
          {"com_along_mm", startup.com_along_mm},
          {columns::kActuatorPower, startup.actuator_power_W},
          {"actuator_work_J", startup.actuator_work_J}};
}

nlohmann::json WarningChecksJson(const RunWarnings& warnings) {
  nlohmann::json checks = nlohmann::json::object();
  for (int c = 0; c < kRunWarningCheckCount; ++c) {
    checks[kRunWarningChecks[c].column] = warnings.failed[c];
  }
  return checks;
}

}  // namespace

nlohmann::json ClosedLoopSummaryJson(const ClosedLoopResult& result) {
  nlohmann::json summary = SwimMetricsJson(result.swim);
  const EnergyMetrics& energy = result.energy;
  nlohmann::json& cycles = summary["per_cycle"];
  for (size_t k = 0; k < cycles.size() && k < energy.per_cycle.size(); ++k) {
    const EnergyCycle& c = energy.per_cycle[k];
    for (size_t q = 0; q < c.actuator_power_W.size(); ++q) {
      cycles[k][columns::LinkResult(static_cast<int>(q + 1), columns::kActuatorPower)] =
          c.actuator_power_W[q];
    }
    cycles[k][columns::kActuatorPower] = c.actuator_power_W_total;
    cycles[k][columns::kFluidPower] = c.fluid_power_W;
    cycles[k][columns::kHingeDampingPower] = c.hinge_damping_power_W;
    cycles[k][columns::kSteppingPower] = c.stepping_power_W;
    cycles[k][columns::kElasticEnergy] = c.elastic_energy_J;
    cycles[k][columns::kStoredEnergyChange] = c.stored_energy_change_J;
    cycles[k][columns::kLighthillEfficiency] = c.lighthill_efficiency;
    cycles[k][columns::kCostOfTransport] = c.cost_of_transport_J_m;
    if (energy.electrical) {
      for (size_t q = 0; q < c.electrical_power_W.size(); ++q) {
        cycles[k][columns::LinkResult(static_cast<int>(q + 1), columns::kElectricalPower)] =
            c.electrical_power_W[q];
      }
      cycles[k][columns::kElectricalPower] = c.electrical_power_W_total;
      cycles[k][columns::kElectromechanicalEfficiency] = c.electromechanical_efficiency;
    }
  }
  summary["metrics_from_cycle"] = result.swim.from_cycle;
  summary["metrics_cycles"] = MetricCyclesText(result);
  if (result.swim.from_cycle > 1) summary["startup"] = StartupJson(result);
  summary["warnings"] = ClosedLoopWarningLines(result);
  summary["notes"] = result.notes;
  summary["warning_checks"] = WarningChecksJson(ClosedLoopWarnings(result));
  summary[columns::kActuatorPower] = energy.actuator_power_W_total;
  summary[columns::kFluidPower] = energy.fluid_power_W;
  summary[columns::kHingeDampingPower] = energy.hinge_damping_power_W;
  summary[columns::kSteppingPower] = energy.stepping_power_W;
  summary[columns::kElasticEnergy] = energy.elastic_energy_J;
  summary[columns::kTowingDrag] = energy.towing_drag_N;
  summary[columns::kLighthillEfficiency] = energy.lighthill_efficiency;
  summary[columns::kCostOfTransport] = energy.cost_of_transport_J_m;
  if (energy.electrical) {
    summary[columns::kElectricalPower] = energy.electrical_power_W_total;
    summary[columns::kElectromechanicalEfficiency] = energy.electromechanical_efficiency;
  }
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
                     {"peak_moment_Nm", t.peak_moment_Nm},
                     {"clamped_fraction", t.clamped_fraction},
                     {columns::kActuatorPower,
                      q < energy.actuator_power_W.size() ? energy.actuator_power_W[q] : 0.0}});
    if (q < energy.electrical_power_W.size()) {
      links.back()[columns::kElectricalPower] = energy.electrical_power_W[q];
    }
  }
  summary["controller"] = result.controller;
  summary["actuation"] = ChoiceText(kActuationNames, result.actuation);
  summary["clamp_enabled"] = result.clamp_enabled;
  summary["v_max_V"] = result.v_max_V;
  summary["period_s"] = result.period_s;
  summary["timestep_s"] = result.timestep_s;
  summary["links"] = links;
  return summary;
}

nlohmann::json ClosedLoopProvenance(const ScenarioConfig& scenario) {
  return {{kProgramVersion, ProgramVersion()},
          {kResolvedScenario, ResolvedScenarioToml(scenario)},
          {kModelSha256, ScenarioModelSha256(scenario)}};
}

ScenarioConfig ScenarioOfSummary(const std::string& summary_path) {
  const nlohmann::json summary =
      nlohmann::json::parse(ReadTextFile(summary_path, "run summary"), nullptr, false);
  const auto recorded = [&](const char* key) -> std::string {
    const std::string dotted = std::string(kInputs) + "." + key;
    if (!summary.is_object() || !summary.contains(kInputs) || !summary[kInputs].is_object() ||
        !summary[kInputs].contains(key) || !summary[kInputs][key].is_string()) {
      throw InputError(InputProblem::kMissing, {summary_path}, dotted,
                       "not a closed-loop run's summary with its provenance (no string " + dotted +
                           ")");
    }
    return summary[kInputs][key].get<std::string>();
  };
  const std::string toml = recorded(kResolvedScenario);
  const std::string sha256 = recorded(kModelSha256);
  const ScenarioConfig scenario =
      ParseScenario(toml, summary_path + " (" + kInputs + "." + kResolvedScenario + ")");
  RequireRecordedModel(
      summary_path, sha256, ScenarioModelSha256(scenario),
      scenario.model.Generated() ? "the generated flagellum" : "'" + scenario.model.path + "'");
  return scenario;
}

std::string ModelOfGaitSummary(const std::string& summary_path, const nlohmann::json& inputs) {
  if (!inputs.is_object() || !inputs.contains("model") || !inputs["model"].is_string()) {
    throw InputError(InputProblem::kMissing, {summary_path}, std::string(kInputs) + ".model",
                     "no field " + std::string(kInputs) + ".model");
  }
  const std::string path = inputs["model"].get<std::string>();
  if (inputs.contains(kModelSha256) && inputs[kModelSha256].is_string()) {
    RequireRecordedModel(summary_path, inputs[kModelSha256].get<std::string>(),
                         ModelFileSha256(path), "'" + path + "'");
  }
  return path;
}

void WriteClosedLoopOutputs(const std::string& dir, const ClosedLoopResult& result,
                            const ScenarioConfig& scenario, const nlohmann::json& inputs,
                            const RunFileFormats& formats) {
  nlohmann::json all = inputs;
  all.update(ClosedLoopProvenance(scenario));
  std::string source;
  WriteRunOutputs(dir, ClosedLoopSamplesCsv(result), RecordedStatesCsv(result.states),
                  ClosedLoopSummaryJson(result), all, formats, ScenarioModelXml(scenario, &source));
}

}  // namespace ipmc
