#include "sim/runs/gait_command.h"

#include <filesystem>
#include <optional>

#include "sim/core/data_paths.h"
#include "sim/core/simulation.h"
#include "sim/base/error.h"
#include "sim/io/files.h"
#include "sim/runs/output.h"

namespace ipmc {
namespace {

constexpr char kCommand[] = "gait";

OptionTable<GaitCommand> MakeGaitOptions() {
  OptionTable<GaitCommand> table(kCommand,
                                 "Run a prescribed joint-space gait and measure the swim");
  OptionInfo model{"model", "", "an MJCF file with servo_* actuators", "The model"};
  model.default_text = "models/flagellum3.xml";
  table.AddPath(model,
                [](GaitCommand& c) -> std::string& { return c.model; });
  OptionInfo gait{"gait", "", "", "sine | square | csv"};
  gait.choices = {"sine", "square", "csv"};
  table.Add<std::string>(gait, [](GaitCommand& c) -> std::string& { return c.gait; });
  table.Add<double>({"frequency_Hz", "Hz", "finite and nonzero", "Gait frequency"},
                    [](GaitCommand& c) -> double& { return c.frequency_Hz; });
  table.Add<double>({"amplitude_rad", "rad", "finite", "Joint amplitude"},
                    [](GaitCommand& c) -> double& { return c.amplitude_rad; });
  table.Add<double>({"phase_lag_rad", "rad", "finite",
                     "Sine: phase lag between consecutive joints; > 0 sends the wave to the tail"},
                    [](GaitCommand& c) -> double& { return c.phase_lag_rad; });
  table.Add<std::vector<double>>({"amplitudes_rad", "rad", "one per driven joint",
                                  "Sine: per-joint amplitudes"},
                                 [](GaitCommand& c) -> std::vector<double>& { return c.amplitudes_rad; });
  table.Add<std::vector<double>>({"phases_rad", "rad", "one per driven joint",
                                  "Sine: per-joint phases"},
                                 [](GaitCommand& c) -> std::vector<double>& { return c.phases_rad; });
  table.AddPath({"csv", "", "a CSV file", "CSV gait: time_s, q_1..q_n [rad]"},
                [](GaitCommand& c) -> std::string& { return c.csv; });
  table.Add<int>({"cycles", "", ">= 1", "Number of gait cycles"},
                 [](GaitCommand& c) -> int& { return c.run.cycles; });
  table.Add<int>({"samples_per_cycle", "", ">= 1", "Time-series samples per cycle"},
                 [](GaitCommand& c) -> int& { return c.run.samples_per_cycle; });
  OptionInfo out{"out", "", "a folder", "Folder for timeseries.csv, states.csv and summary.json"};
  out.aliases = {"o"};
  table.AddPath(out, [](GaitCommand& c) -> std::string& { return c.out; });
  table.Add<bool>({"allow_long", "", "",
                   "Run even beyond 1e8 steps or 2 GB of recorded samples (refused otherwise, "
                   "with the estimate)"},
                  [](GaitCommand& c) -> bool& { return c.run.allow_long; });
  return table;
}

std::string AbsolutePath(const std::string& path) {
  return std::filesystem::absolute(path).lexically_normal().string();
}

}  // namespace

GaitCommand::GaitCommand() : model(ModelsDir() + "/flagellum3.xml") {}

const OptionTable<GaitCommand>& GaitOptions() {
  static const OptionTable<GaitCommand> table = MakeGaitOptions();
  return table;
}

int CountServos(const mjModel* m) {
  int count = 0;
  for (int a = 0; a < m->nu; ++a) {
    const char* name = mj_id2name(m, mjOBJ_ACTUATOR, a);
    if (name && std::string(name).rfind("servo_", 0) == 0) ++count;
  }
  return count;
}

std::unique_ptr<Gait> MakeGait(const GaitCommand& command, int joints) {
  if (command.gait == "csv") {
    if (command.csv.empty()) {
      throw FieldError("gait: csv must name the file of the CSV trajectory", "csv", "a CSV file");
    }
    return LoadCsvGait(command.csv, joints);
  }
  if (command.gait == "square") {
    SquareStrokeConfig config;
    config.frequency_Hz = command.frequency_Hz;
    config.amplitude_rad = command.amplitude_rad;
    config.joints = joints;
    return MakeSquareStroke(config);
  }
  SineGaitConfig config =
      TravellingWave(joints, command.frequency_Hz, command.amplitude_rad, command.phase_lag_rad);
  if (!command.amplitudes_rad.empty()) config.amplitude_rad = command.amplitudes_rad;
  if (!command.phases_rad.empty()) config.phase_rad = command.phases_rad;
  if (static_cast<int>(config.amplitude_rad.size()) != joints) {
    throw FieldError("gait: amplitudes_rad needs " + std::to_string(joints) +
                         " values (one per driven joint)",
                     "amplitudes_rad", std::to_string(joints) + " values");
  }
  return MakeSineGait(config);
}

GaitRunResult RunGaitCommand(const GaitCommand& command,
                             const std::function<void(double period_s)>& on_start,
                             const std::function<void(double t_s)>& on_sample) {
  if (!command.out.empty()) {
    try {
      CheckRunOutputDirectory(kCommand, "out", command.out, {command.model, command.csv});
    } catch (const std::invalid_argument& error) {
      throw FieldError(error.what(), "out", "a folder whose files are not inputs");
    }
  }
  Simulation sim(LoadModelFile(command.model), command.model);
  const std::unique_ptr<Gait> gait = MakeGait(command, CountServos(sim.model()));
  std::optional<DirectoryLock> hold;  // one run per output directory
  if (!command.out.empty()) hold.emplace(command.out);
  if (on_start) on_start(gait->Period_s());
  GaitRunOptions options = command.run;
  options.on_sample = on_sample;
  const GaitRunResult result = RunGait(sim, *gait, options);
  if (!command.out.empty()) {
    const nlohmann::json inputs = {{"model", AbsolutePath(command.model)},
                                   {"gait", command.gait},
                                   {"frequency_Hz", command.frequency_Hz},
                                   {"amplitude_rad", command.amplitude_rad},
                                   {"phase_lag_rad", command.phase_lag_rad},
                                   {"cycles", command.run.cycles},
                                   {"csv", command.csv}};
    WriteGaitOutputs(command.out, result, inputs);
  }
  return result;
}

}  // namespace ipmc
