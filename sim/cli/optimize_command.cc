#include "sim/cli/optimize_command.h"

#include <csignal>
#include <cstdio>
#include <string>

#include "plugin/base/numbers.h"
#include "sim/cli/interrupt.h"

namespace ipmc {

void AddOptimizeCommand(CLI::App& app, OptimizeArgs& args) {
  AddTableCommand(app, OptimizeOptionTable(), args);
}

int RunOptimizeCommandLine(const OptimizeArgs& args) {
  if (!args.Chosen()) return -1;
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
  const nlohmann::ordered_json& result = outcome.result;
  std::printf("%s, %d evaluations (%d from the journal); stop: %s\n",
              result["algorithm"].get<std::string>().c_str(), outcome.evaluations,
              outcome.resumed, result["stop_reason"].get<std::string>().c_str());
  if (result["best"].is_null()) {
    std::printf("no feasible design\n");
  } else {
    const auto& best = result["best"];
    std::printf("best (start %d, evaluation %d): %s = %s\n", best["start"].get<int>(),
                best["evaluation"].get<int>() + 1, plan.config.objective.c_str(),
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
