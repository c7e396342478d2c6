#include "sim/cli/run_command.h"

#include <cstdio>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/cli/command.h"
#include "sim/cli/render_command.h"
#include "sim/cli/run_print.h"
#include "sim/batch/sweep.h"
#include "plugin/base/error.h"
#include "sim/io/files.h"
#include "sim/io/toml.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/runs/output.h"
#include "sim/core/scenario.h"

namespace ipmc {
namespace {

// --allow-long: lifts the run size limits (sim/core/step_count.h).
void AddAllowLongFlag(CLI::App* cmd, bool& allow) {
  cmd->add_flag("--allow-long", allow,
                "Run even beyond 1e8 steps or 2 GB of recorded samples (refused otherwise, with "
                "the estimate)");
}

void PrintClosedLoopResult(const ClosedLoopResult& r) {
  std::printf("%s controller, %s actuation, wave period %.6g s, time step %.3g s\n",
              r.controller.c_str(), r.actuation.c_str(), r.period_s, r.timestep_s);
  PrintMetricCycles(r.swim);
  std::printf("%4s %12s %14s %16s %20s %13s %16s\n", "link", "iae_mm_s", "itae_mm_s2",
              "max_abs_error_mm", "max_abs_reference_mm", "rms_voltage_V", "clamped_fraction");
  for (size_t q = 0; q < r.links.size(); ++q) {
    const LinkTracking& t = r.links[q];
    std::printf("%4zu %12.5g %14.6g %16.5g %20.5g %13.4g %16.4f\n", q + 1, t.iae_mm_s,
                t.itae_mm_s2, t.max_abs_error_mm, t.max_abs_reference_mm, t.rms_voltage_V,
                t.clamped_fraction);
  }
  PrintSwimMetrics(r.swim);
  PrintEnergy(r.energy);
}

// A path made absolute, so that a run's outputs name their inputs from
// anywhere (render reads them back).
std::string AbsolutePath(const std::string& path) {
  return std::filesystem::absolute(path).lexically_normal().string();
}

bool IsRunSummary(const std::string& path) {
  return std::filesystem::path(path).extension() == ".json";
}

// The scenario file with the --set and --cycles overrides
// (ScenarioWithSettings, sim/core/scenario_overrides.h).
ScenarioConfig ScenarioWithOptions(const RunArgs& args) {
  std::vector<ScenarioSetting> settings;
  for (const std::string& set : args.sets) settings.push_back(SetOption("run", set));
  if (args.command->count("--cycles") > 0) {
    const std::string cycles = std::to_string(args.cycles);
    settings.push_back({"--cycles " + cycles, "cycles=" + cycles});
  }
  return ScenarioWithSettings("run", args.scenario_path, settings);
}

}  // namespace

void AddRunCommand(CLI::App& app, RunArgs& args) {
  CLI::App* cmd = AddCommand(app, "run", "Run a closed-loop scenario file (TOML)");
  cmd->add_option("scenario", args.scenario_path,
                  "Scenario file (TOML), or a run's summary.json to run it again")
      ->required();
  cmd->add_option("--set", args.sets,
                  "KEY=VALUE: set a scenario key (dotted, as in sweep files; VALUE is TOML: "
                  "strings in quotes); repeatable; see `ipmc-swim keys`")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  cmd->add_option("--cycles", args.cycles, "Wave periods to run (= --set cycles=N)");
  cmd->add_option("-o,--out", args.out_dir, "Output directory (overrides output.dir)");
  cmd->add_option("--format", args.formats,
                  "Also write the whole run as run.mat (mat: MATLAB/Octave) or run.h5 (h5: "
                  "HDF5); repeatable or comma-separated; csv (always written) is accepted")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  cmd->add_option("--video", args.video_path,
                  "Also film the run into this MP4 (from its recorded states; see `render`)");
  AddAllowLongFlag(cmd, args.allow_long);
  AddVideoOptions(cmd, args.film, "Video (with --video)", "--film-cycles");
  args.command = cmd;
}

int RunScenarioCommand(const RunArgs& args) {
  if (args.video_path.empty() && AnyVideoOptionGiven(args.command)) {
    throw std::invalid_argument("run: video options need --video FILE.mp4");
  }
  const bool rerun = IsRunSummary(args.scenario_path);
  const bool overridden = !args.sets.empty() || args.command->count("--cycles") > 0;
  if (rerun && overridden) {
    throw std::invalid_argument(
        "run: --set and --cycles apply to scenario files, not to a run's summary.json");
  }
  ScenarioConfig scenario =
      rerun ? ScenarioOfSummary(args.scenario_path)
            : overridden ? ScenarioWithOptions(args) : LoadScenario(args.scenario_path);
  scenario.allow_long_run = args.allow_long;
  nlohmann::json inputs = {{"scenario", AbsolutePath(args.scenario_path)}};
  if (rerun) inputs = {{"rerun_of", AbsolutePath(args.scenario_path)}};
  if (!args.sets.empty()) inputs["set"] = args.sets;
  if (args.command->count("--cycles") > 0) inputs["cycles"] = args.cycles;
  // A re-run writes only where --out says, never over the run it repeats.
  const std::string dir = args.out_dir.empty() && !rerun ? scenario.output_dir : args.out_dir;
  const RunFileFormats formats = ParseRunFileFormats(args.formats);
  if ((formats.mat || formats.hdf5) && dir.empty()) {
    throw std::invalid_argument("run: --format mat or h5 needs an output directory (--out DIR)");
  }
  // Output locations are checked before the run, not after it.
  if (!dir.empty()) CheckRunOutputDirectory("run", "--out", dir, {args.scenario_path});
  if (!args.video_path.empty()) {
    RefuseOverwritingInputs("run", "--video", args.video_path, {args.scenario_path});
    RequireWritableParent(args.video_path);
  }
  // One run per output directory, from the start of the work to its end.
  std::optional<DirectoryLock> hold;
  if (!dir.empty()) hold.emplace(dir);
  // The results are printed and written before the film is made.
  RunScenarioFilmed(scenario, args.film, args.video_path,
                          [&](const ClosedLoopResult& result) {
                            PrintClosedLoopResult(result);
                            if (dir.empty()) return;
                            WriteClosedLoopOutputs(dir, result, scenario, inputs, formats);
                            PrintWritten(dir, formats);
                          });
  return 0;
}

}  // namespace ipmc
