#include "sim/cli/gait_command.h"

#include <cstdio>
#include <optional>

#include "sim/cli/run_print.h"
#include "sim/cli/run_watch.h"

namespace ipmc {
namespace {

void PrintGaitResult(const GaitRunResult& r) {
  std::printf("%s, period %.6g s, time step %.3g s\n", r.gait.c_str(), r.period_s, r.timestep_s);
  PrintSwimMetrics(r.swim);
  std::printf("servo tracking: max error %.3g rad for references up to %.3g rad\n",
              r.max_tracking_error_rad, r.max_reference_rad);
}


}  // namespace

void AddGaitCommand(CLI::App& app, GaitArgs& args) { AddTableCommand(app, GaitOptions(), args); }

int RunGaitCommandLine(const GaitArgs& args) {
  if (!args.Chosen()) return -1;
  const GaitCommand& command = args.spec;
  std::optional<RunWatch> watch;
  const GaitRunResult result = TranslatingFieldErrors(GaitOptions(), [&] {
    return RunGaitCommand(
        command, [&](double period_s) { watch.emplace("gait", command.run.cycles * period_s); },
        [&](double t_s) { watch->At(t_s); });
  });
  if (watch) watch->Finish();
  PrintGaitResult(result);
  if (!command.out.empty()) PrintWritten(command.out);
  return 0;
}

}  // namespace ipmc
