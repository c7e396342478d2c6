#include "sim/runs/run_command.h"

#include <filesystem>
#include <stdexcept>
#include <utility>

#include "sim/base/error.h"
#include "sim/core/scenario_overrides.h"

namespace ipmc {
namespace {

constexpr char kCommand[] = "run";

OptionTable<RunCommand> MakeRunOptions() {
  OptionTable<RunCommand> table(kCommand, "Run a closed-loop scenario file (TOML)");
  OptionInfo scenario{"scenario", "", "a TOML file or a summary.json",
                      "Scenario file (TOML), or a run's summary.json to run it again"};
  scenario.positional = true;
  scenario.required = true;
  table.AddPath(scenario, [](RunCommand& c) -> std::string& { return c.scenario; });
  OptionInfo set{"set", "", "KEY=VALUE, repeatable",
                 "Set a scenario key (dotted, as in sweep files; VALUE is TOML: strings in "
                 "quotes); see `ipmc-swim keys`. Python: keyword overrides"};
  set.command_line_only = true;
  table.Add<std::vector<std::string>>(set,
                                      [](RunCommand& c) -> std::vector<std::string>& { return c.set; });
  OptionInfo cycles{"cycles", "", ">= 1", "Wave periods to run (= set cycles=N)"};
  cycles.command_line_only = true;
  cycles.default_text = "the scenario's";
  table.Add<int>(cycles, [](RunCommand& c) -> int& { return c.cycles; });
  OptionInfo out{"out", "", "a folder",
                 "Output folder for timeseries.csv, states.csv, model.xml and summary.json (the command "
                 "line's default: the scenario's output.dir)"};
  out.aliases = {"o"};
  table.AddPath(out, [](RunCommand& c) -> std::string& { return c.out; });
  OptionInfo formats{"formats", "", "csv, mat, h5 (hdf5); repeatable or comma-separated",
                     "Also write the whole run as run.mat (MATLAB/Octave) or run.h5 (HDF5); csv "
                     "(always written) is accepted"};
  formats.aliases = {"format"};
  table.Add<std::vector<std::string>>(
      formats, [](RunCommand& c) -> std::vector<std::string>& { return c.formats; });
  OptionInfo video{"video", "", "an MP4 file",
                   "Also film the run into this MP4 (from its recorded states; see `render`)"};
  video.command_line_only = true;
  table.AddPath(video, [](RunCommand& c) -> std::string& { return c.video; });
  table.Add<bool>({"allow_long", "", "",
                   "Run even beyond 1e8 steps or 2 GB of recorded samples (refused otherwise, "
                   "with the estimate)"},
                  [](RunCommand& c) -> bool& { return c.allow_long; });
  return table;
}

// A path made absolute, so that a run's outputs name their inputs from
// anywhere (render reads them back).
std::string AbsolutePath(const std::string& path) {
  return std::filesystem::absolute(path).lexically_normal().string();
}

bool IsRunSummary(const std::string& path) {
  return std::filesystem::path(path).extension() == ".json";
}

}  // namespace

const OptionTable<RunCommand>& RunOptions() {
  static const OptionTable<RunCommand> table = MakeRunOptions();
  return table;
}

RunPlan PlanRunCommand(const RunCommand& command, const OptionGiven& given) {
  const bool rerun = IsRunSummary(command.scenario);
  const bool cycles_given = given && given("cycles");
  const bool overridden = !command.set.empty() || cycles_given;
  if (rerun && overridden) {
    throw FieldError("run: set and cycles apply to scenario files, not to a run's summary.json",
                     "set", "a scenario file's keys");
  }
  ScenarioConfig scenario;
  nlohmann::json inputs = {{"scenario", AbsolutePath(command.scenario)}};
  if (rerun) {
    scenario = ScenarioOfSummary(command.scenario);
    inputs = {{"rerun_of", AbsolutePath(command.scenario)}};
  } else if (overridden) {
    // ScenarioWithSettings (sim/core/scenario_overrides.h), in order.
    std::vector<ScenarioSetting> settings;
    for (const std::string& set : command.set) settings.push_back(SetOption(kCommand, set));
    if (cycles_given) {
      const std::string cycles = std::to_string(command.cycles);
      settings.push_back({OptionFlag("cycles") + " " + cycles, "cycles=" + cycles});
    }
    scenario = ScenarioWithSettings(kCommand, command.scenario, settings);
  } else {
    scenario = LoadScenario(command.scenario);
  }
  if (!command.set.empty()) inputs["set"] = command.set;
  if (cycles_given) inputs["cycles"] = command.cycles;
  // A re-run writes only where out says, never over the run it repeats.
  RunCommand planned = command;
  if (planned.out.empty() && !rerun) planned.out = scenario.output.dir;
  return PlanRunCommand(planned, std::move(scenario), std::move(inputs), {command.scenario});
}

RunPlan PlanRunCommand(const RunCommand& command, ScenarioConfig scenario, nlohmann::json inputs,
                       const std::vector<std::string>& input_files) {
  RunPlan plan;
  plan.scenario = std::move(scenario);
  plan.scenario.run.allow_long = command.allow_long;
  plan.inputs = std::move(inputs);
  plan.dir = command.out;
  plan.formats = ParseRunFileFormats(command.formats);
  plan.video = command.video;
  if ((plan.formats.mat || plan.formats.hdf5) && plan.dir.empty()) {
    throw FieldError("run: formats mat or h5 need an output folder (out)", "formats",
                     "csv without out");
  }
  // Output locations are checked before the run, not after it.
  try {
    if (!plan.dir.empty()) CheckRunOutputDirectory(kCommand, "out", plan.dir, input_files);
  } catch (const std::invalid_argument& error) {
    throw FieldError(error.what(), "out", "a folder whose files are not inputs");
  }
  if (!plan.video.empty()) {
    try {
      RefuseOverwritingInputs(kCommand, "video", plan.video, input_files);
    } catch (const std::invalid_argument& error) {
      throw FieldError(error.what(), "video", "a file that is not an input");
    }
    RequireWritableParent(plan.video);
  }
  // One run per output directory, from the start of the work to its end.
  if (!plan.dir.empty()) plan.lock = std::make_shared<DirectoryLock>(plan.dir);
  return plan;
}

void WriteRunOutputs(const RunPlan& plan, const ClosedLoopResult& result) {
  if (plan.dir.empty()) return;
  WriteClosedLoopOutputs(plan.dir, result, plan.scenario, plan.inputs, plan.formats);
}

}  // namespace ipmc
