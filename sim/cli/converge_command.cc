#include "sim/cli/converge_command.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "renders/figures.h"

namespace ipmc {
namespace {

void PrintReference(const char* what, const char* unit, const ConvergeReference& reference) {
  std::printf("  converged %s %.6g %s +- %.2g (%.2g %%)\n", what, reference.value, unit,
              reference.uncertainty,
              reference.value != 0.0 ? 100.0 * reference.uncertainty / std::abs(reference.value)
                                     : 0.0);
}

void PrintRun(const ConvergeRun& run, const ConvergeStudy& study) {
  const double swim_error = ConvergeError(run.swim_mm, study.swim);
  const double power_error = ConvergeError(run.fluid_power_W, study.fluid_power);
  const bool converged = std::abs(swim_error) <= kConvergedError &&
                         std::abs(power_error) <= kConvergedError;
  std::printf("  %-30s %12.6g %+9.3f %% %12.6g %+9.3f %% %10.3g %s%s\n", run.setting.c_str(),
              run.swim_mm, 100.0 * swim_error, run.fluid_power_W, 100.0 * power_error,
              run.cost_s_per_s, converged ? "within 1 %" : "",
              run.warnings > 0 ? (" (" + std::to_string(run.warnings) + " warnings)").c_str() : "");
}

}  // namespace

void AddConvergeCommand(CLI::App& app, ConvergeArgs& args) {
  AddTableCommand(app, ConvergeOptions(), args);
}

int RunConvergeCommandLine(const ConvergeArgs& args) {
  if (!args.Chosen()) return -1;
  const ConvergeOutcome outcome = TranslatingFieldErrors(
      ConvergeOptions(), [&] { return RunConvergeCommand(args.spec); });
  std::printf("converge %s: the last of %d cycles; swim = centre of mass along [mm], fluid "
              "power [W], cost = wall s per simulated s\n",
              args.spec.scenario.c_str(), args.spec.cycles);
  for (const ConvergeStudy& study : outcome.studies) {
    std::printf("%s:\n", study.name.c_str());
    PrintReference("swim", "mm", study.swim);
    PrintReference("fluid power", "W", study.fluid_power);
    std::printf("  %-30s %12s %11s %12s %11s %10s\n", "setting", "swim_mm", "error",
                "fluid_W", "error", "cost");
    ConvergeRun scenario = outcome.scenario;
    scenario.setting = "the scenario's";
    PrintRun(scenario, study);
    std::string cheapest;
    double cheapest_cost = INFINITY;
    for (const ConvergeRun& run : study.runs) {
      PrintRun(run, study);
      if (std::abs(ConvergeError(run.swim_mm, study.swim)) <= kConvergedError &&
          std::abs(ConvergeError(run.fluid_power_W, study.fluid_power)) <= kConvergedError &&
          run.cost_s_per_s < cheapest_cost) {
        cheapest = run.setting;
        cheapest_cost = run.cost_s_per_s;
      }
    }
    std::printf("  within 1 %% in both at the least cost: %s\n",
                cheapest.empty() ? "none of these runs (refine further)" : cheapest.c_str());
  }
  if (outcome.table_path.empty()) return 0;
  const std::string png =
      (std::filesystem::path(args.spec.out) / "converge.png").string();
  DrawConvergeFigure(outcome.table_path, png);
  std::printf("wrote %s and %s\n", outcome.table_path.c_str(), png.c_str());
  return 0;
}

}  // namespace ipmc
