#include "sim/cli/run_command.h"

#include <cstdio>

#include "sim/base/error.h"
#include "sim/cli/render_command.h"
#include "sim/cli/run_print.h"
#include "sim/runs/run_warnings.h"

namespace ipmc {
namespace {

void PrintClosedLoopResult(const ClosedLoopResult& r) {
  for (const std::string& note : r.notes) std::fprintf(stderr, "note: %s\n", note.c_str());
  std::printf("%s %s, %s actuation, wave period %.6g s, time step %.3g s\n",
              r.open_loop ? "open-loop" : r.controller.c_str(),
              r.open_loop ? (r.controller + " drive").c_str() : "controller",
              ChoiceText(kActuationNames, r.actuation), r.period_s, r.timestep_s);
  PrintMetricCycles(r);
  std::printf("%4s %12s %14s %16s %20s %13s %16s\n", "link", "iae_mm_s", "itae_mm_s2",
              "max_abs_error_mm", "max_abs_reference_mm", "rms_voltage_V", "clamped_fraction");
  for (size_t q = 0; q < r.links.size(); ++q) {
    const LinkTracking& t = r.links[q];
    std::printf("%4zu %12.5g %14.6g %16.5g %20.5g %13.4g %16.4f\n", q + 1, t.iae_mm_s,
                t.itae_mm_s2, t.max_abs_error_mm, t.max_abs_reference_mm, t.rms_voltage_V,
                t.clamped_fraction);
  }
  PrintSwimMetrics(r.swim, ClosedLoopWarningLines(r));
  PrintEnergy(r.energy);
  PrintStartup(r);
}

}  // namespace

void AddRunCommand(CLI::App& app, RunArgs& args) {
  AddTableCommand(app, RunOptions(), args);
  AddVideoOptions(args.command, args.film, "Video (with --video)", "--film-cycles");
}

int RunRunCommandLine(const RunArgs& args) {
  if (!args.Chosen()) return -1;
  const RunCommand& command = args.spec;
  const RunPlan plan = TranslatingFieldErrors(RunOptions(), [&] {
    if (command.video.empty() && AnyVideoOptionGiven(args.command)) {
      throw FieldError("run: film options need video FILE.mp4", "video", "an MP4 file");
    }
    return PlanRunCommand(command, args.Given());
  });
  // The results are printed and written before the film is made.
  TranslatingFilmErrors("--film-cycles", [&] {
    SimulateScenarioWithProgress(plan.scenario, args.film, plan.video,
                                 [&](const ClosedLoopResult& result) {
                                   PrintClosedLoopResult(result);
                                   if (plan.dir.empty()) return;
                                   WriteRunOutputs(plan, result);
                                   PrintWritten(plan.dir, plan.formats);
                                 });
  });
  return 0;
}

}  // namespace ipmc
