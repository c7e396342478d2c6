// Design optimisation from Python: what `ipmc-swim optimize` computes and
// writes (sim/optimize/optimize_run.h), returning result.json as a dict.
#include <atomic>
#include <string>

#include "sim/optimize/optimize_run.h"
#include "sim/python/convert.h"

namespace ipmc::python {
namespace {

py::object Optimize(const py::object& path_arg, const py::dict& kwargs,
                    const py::object& progress_callback) {
  Options options("optimize", kwargs);
  OptimizeCommand file;
  file.file = PathText(path_arg, "file");
  const OptimizeCommand command = ReadCommandKeywords(options, OptimizeOptionTable(), file);
  const OptimizePlan plan = WithoutGil([&] { return PlanOptimizeCommand(command); });
  const int starts = plan.config.multistart + 1;
  Progress progress(progress_callback, static_cast<double>(plan.config.max_evaluations) * starts);
  // Ctrl-C lets the running evaluations finish and starts no other; the
  // journal keeps them for resume=True.
  const OptimizeOutcome outcome = Interruptible([&](const std::atomic<bool>& stop) {
    OptimizeHooks hooks;
    hooks.on_evaluation = [&](const OptimizeProgress& p) { progress.Report(p.done, true); };
    hooks.stop_requested = [&stop] { return stop.load(); };
    return RunOptimizeCommand(plan, hooks);
  });
  return ToPython(outcome.result);
}

}  // namespace

void BindOptimize(py::module_& m) {
  m.def("optimize", &Optimize, py::arg("file"), py::arg("options"), py::arg("progress"));
}

}  // namespace ipmc::python
