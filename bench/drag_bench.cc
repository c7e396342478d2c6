// Steps per second of the paper's flagellum three ways, in one run:
// bare MuJoCo (no callbacks), with the RFT drag callback, and with
// MuJoCo's built-in ellipsoid fluid model instead. The ratios to the bare
// step are what to compare (Google Benchmark reports items_per_second).
//
//   ./build/bench/drag_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <regex>
#include <string>

#include "bench/ratio_reporter.h"
#include "ipmc_swim/ipmc_swim.h"
#include "sim/core/model_generator.h"
#include "sim/core/simulation.h"

namespace ipmc {
namespace {

std::string FlagellumXml() { return GenerateFlagellumMjcf(FlagellumSpec()); }

// The same body with MuJoCo's own fluid forces (ellipsoid model, water).
std::string BuiltinFluidXml() {
  std::string xml = FlagellumXml();
  xml = std::regex_replace(xml, std::regex("<custom>[\\s\\S]*</custom>\\n"), "");
  xml = std::regex_replace(xml, std::regex("gravity=\"0 0 0\""),
                           "gravity=\"0 0 0\" density=\"1000\" viscosity=\"0.001\"");
  return std::regex_replace(xml, std::regex("<geom "), "<geom fluidshape=\"ellipsoid\" ");
}

// Bends the hinges and lets the body flap back under its own stiffness,
// restarting every 2000 steps so that the motion stays non-trivial.
void StepLoop(benchmark::State& state, const mjModel* m, mjData* d) {
  long steps = 0;
  for (auto _ : state) {
    if (steps % 2000 == 0) {
      mj_resetData(m, d);
      for (int i = m->nq - 3; i < m->nq; ++i) d->qpos[i] = 0.3;
    }
    mj_step(m, d);
    ++steps;
  }
  state.SetItemsProcessed(steps);
}

// Steps `xml` with MuJoCo's callbacks switched off for the duration.
void StepWithoutCallbacks(benchmark::State& state, const std::string& xml) {
  ModelPtr m = LoadModelString(xml);
  DataPtr d(mj_makeData(m.get()));
  mjfGeneric passive = mjcb_passive, control = mjcb_control;
  mjcb_passive = nullptr;
  mjcb_control = nullptr;
  StepLoop(state, m.get(), d.get());
  mjcb_passive = passive;
  mjcb_control = control;
}

void BM_BareMuJoCo(benchmark::State& state) { StepWithoutCallbacks(state, FlagellumXml()); }

void BM_RftDragCallback(benchmark::State& state) {
  ModelPtr m = LoadModelString(FlagellumXml());
  DataPtr d(mj_makeData(m.get()));
  Attach(m.get(), d.get());
  StepLoop(state, m.get(), d.get());
  Detach(d.get());
}

void BM_BuiltinEllipsoidFluid(benchmark::State& state) {
  StepWithoutCallbacks(state, BuiltinFluidXml());
}

BENCHMARK(BM_BareMuJoCo)->MinTime(2.0);
BENCHMARK(BM_RftDragCallback)->MinTime(2.0);
BENCHMARK(BM_BuiltinEllipsoidFluid)->MinTime(2.0);

}  // namespace
}  // namespace ipmc

int main(int argc, char** argv) { return ipmc::RunWithRatios(argc, argv, "BM_BareMuJoCo"); }
