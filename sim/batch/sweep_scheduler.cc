// Running a sweep's points: on a pool of threads, the longest first, each
// writing only its own row.
#include "sim/batch/sweep_scheduler.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <cmath>
#include <exception>
#include <filesystem>
#include <iterator>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/core/data_paths.h"
#include "sim/core/fan_out.h"
#include "sim/batch/sweep_gait.h"
#include "sim/core/sha256.h"
#include "sim/io/columns.h"
#include "sim/io/files.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/runs/output.h"
#include "sim/runs/run_warnings.h"

namespace ipmc {
namespace {

// Physics steps of a point's run, for scheduling (0 for a point that will
// not run; the model's own step, unknown here, counts as kDefaultStep_s).
double EstimatedSteps(const SweepPoint& point) {
  constexpr double kDefaultStep_s = 1e-4;
  if (point.gait) return point.gait->run.cycles / std::abs(point.gait->frequency_Hz) / kDefaultStep_s;
  if (!point.scenario) return 0.0;
  const ScenarioConfig& scenario = *point.scenario;
  return scenario.run.cycles / std::abs(scenario.waveform.frequency_Hz) /
         scenario.run.timestep_s.value_or(kDefaultStep_s);
}

// One point's row; `error` receives the failure, if any. With runs_dir,
// the run's outputs are written there too.
// A gait point's row: `ipmc-swim gait` with the point's options (and, with
// runs_dir, its --out).
std::vector<std::string> RunGaitPoint(const SweepPoint& point, const std::string& runs_dir,
                                      std::vector<std::string> row, std::string* error) {
  GaitCommand command = *point.gait;
  command.out = runs_dir.empty() ? "" : SweepPointRunDir(runs_dir, point.index);
  std::optional<GaitRunResult> result;
  try {
    result = RunGaitCommand(command);
  } catch (const std::exception& failure) {
    *error = OneLine(failure.what());
  }
  row.push_back(result ? columns::kStatusOk : columns::kStatusError);
  row.push_back(result ? "" : *error);
  const std::vector<std::string> cells = GaitResultCells(result ? &*result : nullptr);
  row.insert(row.end(), cells.begin(), cells.end());
  return row;
}

std::vector<std::string> RunPoint(const SweepPlan& plan, const SweepPoint& point,
                                  const std::string& runs_dir, std::string* error) {
  std::vector<std::string> row = {std::to_string(point.index)};
  row.insert(row.end(), point.values.begin(), point.values.end());
  if (point.gait) return RunGaitPoint(point, runs_dir, std::move(row), error);
  std::optional<ClosedLoopResult> result;
  *error = point.error;
  if (point.scenario) {
    try {
      result = SimulateScenario(*point.scenario);
      if (!runs_dir.empty()) {
        const nlohmann::json inputs = {
            {"scenario", plan.base_path}, {"sweep", plan.source}, {"sweep_point", point.index}};
        WriteClosedLoopOutputs(SweepPointRunDir(runs_dir, point.index), *result,
                               *point.scenario, inputs);
      }
    } catch (const std::exception& failure) {
      result.reset();
      *error = OneLine(failure.what());
    }
  }
  row.push_back(result ? columns::kStatusOk : columns::kStatusError);
  row.push_back(result ? "" : *error);
  for (int q = 0; q < plan.links; ++q) {
    if (result && q < static_cast<int>(result->links.size())) {
      const LinkTracking& link = result->links[q];
      const std::vector<double>& power_W = result->energy.actuator_power_W;
      for (double value : {link.iae_mm_s, link.itae_mm_s2, link.rms_voltage_V,
                           link.clamped_fraction, q < static_cast<int>(power_W.size()) ? power_W[q] : 0.0}) {
        row.push_back(FormatShortest(value));
      }
    } else {
      row.insert(row.end(), std::size(columns::kLinkResults), "");
    }
  }
  if (result) {
    const SwimMetrics& swim = result->swim;
    const double last_cycle = swim.per_cycle.empty() ? 0.0 : swim.per_cycle.back().com_along;
    const EnergyMetrics& energy = result->energy;
    for (double value :
         {last_cycle, swim.mean_speed_along_mm_s, swim.reynolds_tip, swim.reynolds_swim,
          energy.actuator_power_W_total, energy.fluid_power_W, energy.hinge_damping_power_W,
          energy.stepping_power_W,
          energy.lighthill_efficiency, energy.cost_of_transport_J_m,
          energy.electrical_power_W_total, energy.electromechanical_efficiency}) {
      row.push_back(FormatShortest(value));
    }
  } else {
    row.insert(row.end(), std::size(columns::kSwimResults), "");
  }
  const std::vector<std::string> warnings =
      result ? RunWarningCells(ClosedLoopWarnings(*result))
             : std::vector<std::string>(RunWarningColumns().size(), "");
  row.insert(row.end(), warnings.begin(), warnings.end());
  return row;
}

}  // namespace

std::string SweepPointRunDir(const std::string& runs_dir, int index) {
  return (std::filesystem::path(runs_dir) / ("point_" + std::to_string(index))).string();
}

std::string SweepRunsDir(const std::string& out_prefix) { return out_prefix + "_runs"; }

SweepShard ParseSweepShard(const std::string& text) {
  const std::string::size_type slash = text.find('/');
  std::optional<long> index, count;
  if (slash != std::string::npos) {
    index = ParseInteger(std::string_view(text).substr(0, slash));
    count = ParseInteger(std::string_view(text).substr(slash + 1));
  }
  if (!index || !count || *count < 1 || *index < 1 || *index > *count || *count > INT_MAX) {
    throw FieldError("sweep: shard must be i/n with 1 <= i <= n (got '" + text + "')", "shard",
                     "i/n with 1 <= i <= n");
  }
  SweepShard shard;
  shard.index = static_cast<int>(*index);
  shard.count = static_cast<int>(*count);
  return shard;
}

SweepTable RunSweep(const SweepPlan& plan, const SweepOptions& options) {
  if (options.jobs < 1) {
    throw FieldError("sweep: jobs must be >= 1 (got " + std::to_string(options.jobs) + ")",
                     "jobs", ">= 1");
  }
  const SweepShard& shard = options.shard;
  if (shard.count < 1 || shard.index < 1 || shard.index > shard.count) {
    throw FieldError("sweep: shard must be i/n with 1 <= i <= n (got " +
                         std::to_string(shard.index) + "/" + std::to_string(shard.count) + ")",
                     "shard", "i/n with 1 <= i <= n");
  }
  std::vector<const SweepPoint*> todo;
  for (const SweepPoint& point : plan.points) {
    if (point.index % shard.count == shard.index - 1) todo.push_back(&point);
  }
  SweepTable table;
  table.columns = SweepColumns(plan);
  table.rows.resize(todo.size());
  // Rows go in index order; runs start longest first, so that the last
  // runs to finish are short ones. Finished points keep their rows.
  std::vector<size_t> schedule;
  for (size_t k = 0; k < todo.size(); ++k) {
    if (options.finished != nullptr && options.finished->count(todo[k]->index) > 0) {
      table.rows[k] = options.finished->at(todo[k]->index);
    } else {
      schedule.push_back(k);
    }
  }
  std::stable_sort(schedule.begin(), schedule.end(), [&](size_t a, size_t b) {
    return EstimatedSteps(*todo[a]) > EstimatedSteps(*todo[b]);
  });

  std::mutex progress_mutex;
  int done = 0;
  std::exception_ptr callback_failure;
  std::atomic<bool> stopped{false};  // by a failed callback: no point starts after it
  const auto start = std::chrono::steady_clock::now();
  // A failing progress report (the journal's record) stops the sweep: no
  // point starts after it, and it is rethrown when the running ones are done.
  FanOut(schedule.size(), options.jobs, [&](size_t slot) {
    if (stopped || (options.stop_requested && options.stop_requested())) return;
    const size_t k = schedule[slot];
    std::string error;
    table.rows[k] = RunPoint(plan, *todo[k], options.runs_dir, &error);
    std::lock_guard<std::mutex> lock(progress_mutex);
    ++done;
    if (!options.on_point_done || callback_failure) return;
    SweepProgress progress;
    progress.done = done;
    progress.total = static_cast<int>(schedule.size());
    progress.point = todo[k]->index;
    progress.ok = table.rows[k][plan.keys.size() + 1] == columns::kStatusOk;
    progress.error = error;
    progress.elapsed_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    progress.row = &table.rows[k];
    try {
      options.on_point_done(progress);
    } catch (...) {
      callback_failure = std::current_exception();
      stopped = true;
    }
  });
  if (callback_failure) std::rethrow_exception(callback_failure);
  table.program_version = ProgramVersion();
  std::map<std::string, std::string> model_sha256;  // by model path; "" for generated
  for (size_t k = 0; k < todo.size(); ++k) {
    const SweepPoint& point = *todo[k];
    if (!table.rows[k].empty() && point.gait) {
      const std::string& model = point.gait->model;
      if (model_sha256.count(model) == 0) {
        std::string sha;
        try {
          sha = Sha256Hex(ReadTextFile(model, "model file"));
        } catch (const std::exception&) {  // the point failed: no model to name
        }
        model_sha256[model] = sha;
      }
      table.provenance[point.index] = {point.scenario_toml, model_sha256[model]};
    }
    if (table.rows[k].empty() || !point.scenario) continue;
    const ScenarioConfig& scenario = *point.scenario;
    const std::string model = scenario.model.Generated() ? "" : scenario.model.path;
    if (scenario.model.Generated() || model_sha256.count(model) == 0) {
      model_sha256[model] = ScenarioModelSha256(scenario);
    }
    table.provenance[point.index] = {ResolvedScenarioToml(scenario), model_sha256[model]};
  }
  // A stopped sweep: the points that did not run have no row.
  table.rows.erase(std::remove_if(table.rows.begin(), table.rows.end(),
                                  [](const std::vector<std::string>& row) { return row.empty(); }),
                   table.rows.end());
  return table;
}

}  // namespace ipmc
