#include "sim/cli/optimize_command.h"

#include <csignal>
#include <filesystem>
#include <stdexcept>
#include <cstdio>
#include <string>

#include "sim/base/numbers.h"
#include "sim/cli/interrupt.h"
#include "sim/io/process.h"

namespace ipmc {

namespace {

// This program, as the job scripts run it.
std::string ThisProgram() {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) throw std::runtime_error("optimize --slurm: cannot find this program's path");
  return self.string();
}

int SubmitToSlurm(const OptimizeArgs& args) {
  OptimizePlan plan;
  const OptimizeSlurmJob job = TranslatingFieldErrors(OptimizeOptionTable(), [&] {
    return ResolveOptimizeSlurm(args.spec, args.slurm_options, ThisProgram(), &plan);
  });
  if (!args.dry_run) CheckSbatchOnPath("optimize");
  WriteOptimizeSlurmJob(job, plan);
  std::printf("wrote %s (%d %s, one per start) and %s\n", job.ArrayScriptPath().c_str(),
              job.starts, job.starts == 1 ? "task" : "tasks", job.MergeScriptPath().c_str());
  if (args.dry_run) {
    std::printf("dry run, nothing submitted; to submit:\n"
                "  jid=$(sbatch --parsable %s) && sbatch --dependency=afterany:$jid %s\n",
                ShellWord(job.ArrayScriptPath()).c_str(), ShellWord(job.MergeScriptPath()).c_str());
    return 0;
  }
  const SlurmJobIds ids =
      SubmitSlurmScripts(job.ArrayScriptPath(), job.MergeScriptPath(), "optimize");
  std::printf("submitted job array %s and merge job %s (after the array); the result goes to "
              "%s/result.json\n",
              ids.array.c_str(), ids.merge.c_str(), job.dir.c_str());
  return 0;
}

}  // namespace

void AddOptimizeCommand(CLI::App& app, OptimizeArgs& args) {
  CLI::App* command = AddTableCommand(app, OptimizeOptionTable(), args);
  CLI::Option* slurm = command->add_flag(
      "--slurm", args.slurm,
      "Run on Slurm: write a job array (one task per start) and a merge job into --out and "
      "submit them (sbatch)");
  command->add_option("--partition", args.slurm_options.partition,
                      "Slurm: partition (default: the cluster's)")
      ->needs(slurm);
  command->add_option("--time", args.slurm_options.time_limit,
                      "Slurm: time limit per task, e.g. 90, 1:30:00, 2-00 (default: the "
                      "partition's)")
      ->needs(slurm);
  command->add_flag("--dry-run", args.dry_run, "Slurm: write the job scripts, do not submit")
      ->needs(slurm);
}

int RunOptimizeCommandLine(const OptimizeArgs& args) {
  if (!args.Chosen()) return -1;
  if (args.slurm) return SubmitToSlurm(args);
  const OptimizePlan plan =
      TranslatingFieldErrors(OptimizeOptionTable(), [&] { return PlanOptimizeCommand(args.spec); });
  OptimizeHooks hooks;
  hooks.on_evaluation = [&](const OptimizeProgress& p) {
    std::fprintf(stderr, "%s\n", OptimizeProgressLine(plan, p).c_str());
  };
  OptimizeOutcome outcome;
  int stop_signal = 0;
  {
    const InterruptAtBoundary interrupt(
        "interrupted: finishing the runs that are running, then stopping (Ctrl-C again stops at "
        "once; finished evaluations stay in " + plan.journal + ")");
    hooks.stop_requested = [&] { return interrupt.Requested(); };
    outcome = RunOptimizeCommand(plan, hooks);
    stop_signal = interrupt.signal();
  }
  if (outcome.stopped) {
    const Interrupted stop(stop_signal != 0 ? stop_signal : SIGINT, "");
    std::fprintf(stderr,
                 "ipmc-swim: interrupted by %s: stopped after %d evaluations, recorded in %s; run "
                 "the same command with --resume to go on\n",
                 stop.SignalName().c_str(), outcome.evaluations, plan.journal.c_str());
    return stop.ExitCode();
  }
  if (outcome.single_start) {
    std::printf("start %d: %d evaluations (%d from the journal), recorded in %s\n",
                *plan.only_start, outcome.evaluations, outcome.resumed, plan.journal.c_str());
    return 0;
  }
  const nlohmann::ordered_json& result = outcome.result;
  std::printf("%s, %d evaluations (%d from the journal); stop: %s\n",
              result["algorithm"].get<std::string>().c_str(), outcome.evaluations,
              outcome.resumed, result["stop_reason"].get<std::string>().c_str());
  if (result["best"].is_null()) {
    std::printf("no feasible design\n");
  } else {
    const auto& best = result["best"];
    std::printf("best (start %d, evaluation %d): %s = %s\n", best["start"].get<int>(),
                best["evaluation"].get<int>(), plan.config.objective.c_str(),
                FormatShortest(best["objective"].get<double>()).c_str());
    for (const auto& [name, value] : best["variables"].items()) {
      std::printf("  %s = %s\n", name.c_str(), FormatShortest(value.get<double>()).c_str());
    }
  }
  std::printf("wrote %s/history.csv, result.json, convergence.csv, convergence.png and best/\n",
              plan.out.c_str());
  return 0;
}

}  // namespace ipmc
