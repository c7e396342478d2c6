// The paper's closed-loop run (scenarios/paper.toml, one 100 s cycle,
// 200 000 steps of 0.5 ms with the controllers, references and swim meter)
// under each fluid model (plugin/fluid/fluid_model.h), in one run so that
// the ratios hold on a loaded machine: RFT (the baseline), regularized
// Stokeslets at the default resolution (one point per blob, 25 points,
// the resistance fitted in time between exact evaluations, the default)
// in free space and near a wall (1 mm gap), Stokeslets recomputed at
// every evaluation (tolerance 0)
// and at twice the points per mm, and on a sheet of 2 and 4 points across
// the width; slender-ribbon theory at its default modes; RFT with the
// coefficients calibrated on the plates (fluid.rft_coefficients = "ribbon",
// its set-up included); the flat plates at 2 points across the width; each
// in the model's inertial dynamics and, the cheaper ones, in Stokes
// dynamics. The runs' simulated time is the same, so the
// ratios are per simulated time. docs/BENCHMARKS.md records them.
//
// BM_FlexibleCycle: the paper's gait on flexible links (n sub-segments per
// link, c1 = 150 um/mm), Stokes dynamics at 1 ms, one 10 s cycle at
// 0.1 Hz, under RFT, slender-ribbon theory at 8 modes and the plates at 4
// points across: each with the cubic fit in time between exact
// evaluations (the default, fit tolerance 1e-4, which keeps the swim and
// the fluid power within 0.1 % of the exact evaluation's,
// docs/FLUIDS.md), with the cached resistance alone (fit tolerance 0,
// shape tolerance 1e-3 rad) and, the ribbon, exact at every step; each
// model's CPU time relative to RFT's at the same n, and each run's swim
// (swim_um) and mean fluid power (fluid_pW).
//
//   ./build/bench/fluid_bench --benchmark_repetitions=3
//   ./build/bench/fluid_bench --benchmark_filter=BM_FlexibleCycle --benchmark_repetitions=3
#include <benchmark/benchmark.h>

#include <string>

#include "bench/ratio_reporter.h"
#include "sim/core/data_paths.h"
#include "sim/core/scenario.h"
#include "sim/runs/closed_loop_run.h"

namespace ipmc {
namespace {

const std::string kPaperScenario = ScenariosDir() + "/paper.toml";

// args: model (0 rft, 1 stokeslets, 2 ribbon, 3 plates), dynamics (0 inertial,
// 1 stokes), variant (0 default, 1 wall gap 1 mm, 2 tolerance 0, 3 twice the
// points, 4 and 5: 2 and 4 points across the width, 6 RFT calibrated on the
// plates).
void BM_PaperCycle(benchmark::State& state) {
  ScenarioConfig scenario = LoadScenario(kPaperScenario);
  scenario.run.cycles = 1;
  scenario.output.dir.clear();
  if (state.range(0) == 1) scenario.fluid.model = "stokeslets";
  if (state.range(0) == 2) scenario.fluid.model = "ribbon";
  if (state.range(0) == 3) {
    scenario.fluid.model = "plates";
    scenario.fluid.parameters["plate_points_across"] = 2;
  }
  if (state.range(1) == 1) scenario.model.dynamics = Dynamics::kStokes;
  if (state.range(2) == 1) scenario.fluid.wall_gap_mm = 1.0;
  if (state.range(2) == 2) scenario.fluid.parameters["stokeslet_shape_tolerance_rad"] = 0.0;
  if (state.range(2) == 3) scenario.fluid.parameters["stokeslet_points_per_mm"] = 2.0 / 1.340;
  if (state.range(2) == 4) scenario.fluid.parameters["stokeslet_width_points"] = 2;
  if (state.range(2) == 5) scenario.fluid.parameters["stokeslet_width_points"] = 4;
  if (state.range(2) == 6) scenario.fluid.rft_coefficients = CoefficientModel::kRibbon;
  for (auto _ : state) benchmark::DoNotOptimize(SimulateScenario(scenario));
}
BENCHMARK(BM_PaperCycle)
    ->Args({0, 0, 0})
    ->Args({1, 0, 0})
    ->Args({1, 0, 1})
    ->Args({1, 0, 2})
    ->Args({1, 0, 3})
    ->Args({1, 0, 4})
    ->Args({1, 0, 5})
    ->Args({0, 1, 0})
    ->Args({1, 1, 0})
    ->Args({1, 1, 1})
    ->Args({2, 0, 0})
    ->Args({2, 1, 0})
    ->Args({0, 0, 6})
    ->Args({0, 1, 6})
    ->Args({3, 0, 0})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

// args: n sub-segments per link; model (0 rft, 2 ribbon, 3 plates);
// resistance (0 cached alone, 2 the fit in time (the default), 3 exact at
// every step).
void BM_FlexibleCycle(benchmark::State& state) {
  const int model = static_cast<int>(state.range(1));
  std::string fluid = model == 2 ? "model = \"ribbon\"\nribbon_modes = 8\n"
                      : model == 3 ? "model = \"plates\"\nplate_points_across = 4\n"
                                   : "model = \"rft\"\n";
  const std::string prefix = model == 2 ? "ribbon_" : "plate_";
  if (model != 0 && state.range(2) == 0) fluid += prefix + "fit_tolerance = 0\n";
  if (state.range(2) == 3) fluid += prefix + "shape_tolerance_rad = 0\n";
  ScenarioConfig scenario = ParseScenario(
      "include = [\"paper.toml\"]\nsegments_per_link = " + std::to_string(state.range(0)) +
          "\ncycles = 1\ntimestep_s = 1e-3\ndynamics = \"stokes\"\n"
          "[waveform]\nc1_um_per_mm = 150.0\nfrequency_Hz = 0.1\n[fluid]\n" + fluid,
      ScenariosDir() + "/flexible_cycle.toml");  // the text's name, beside paper.toml
  scenario.output.dir.clear();
  for (auto _ : state) {
    const ClosedLoopResult result = SimulateScenario(scenario);
    state.counters["swim_um"] = 1e3 * result.swim.per_cycle.at(0).com_along;
    state.counters["fluid_pW"] = 1e12 * result.energy.per_cycle.at(0).fluid_power_W;
  }
}
BENCHMARK(BM_FlexibleCycle)
    ->Args({8, 0, 0})
    ->Args({8, 2, 0})
    ->Args({8, 2, 2})
    ->Args({8, 2, 3})
    ->Args({8, 3, 0})
    ->Args({8, 3, 2})
    ->Args({16, 0, 0})
    ->Args({16, 2, 0})
    ->Args({16, 2, 2})
    ->Args({16, 2, 3})
    ->Args({16, 3, 0})
    ->Args({16, 3, 2})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace
}  // namespace ipmc

int main(int argc, char** argv) {
  return ipmc::RunWithRatios(argc, argv, {"BM_PaperCycle/0/0/0"},
                             {{"BM_PaperCycle/1/1/0", "BM_PaperCycle/0/1/0"},
                              {"BM_PaperCycle/1/1/1", "BM_PaperCycle/0/1/0"},
                              {"BM_PaperCycle/2/1/0", "BM_PaperCycle/0/1/0"},
                              {"BM_PaperCycle/0/1/6", "BM_PaperCycle/0/1/0"},
                              {"BM_FlexibleCycle/8/2/0", "BM_FlexibleCycle/8/0/0"},
                              {"BM_FlexibleCycle/8/2/2", "BM_FlexibleCycle/8/0/0"},
                              {"BM_FlexibleCycle/8/2/3", "BM_FlexibleCycle/8/0/0"},
                              {"BM_FlexibleCycle/8/3/0", "BM_FlexibleCycle/8/0/0"},
                              {"BM_FlexibleCycle/8/3/2", "BM_FlexibleCycle/8/0/0"},
                              {"BM_FlexibleCycle/16/2/0", "BM_FlexibleCycle/16/0/0"},
                              {"BM_FlexibleCycle/16/2/2", "BM_FlexibleCycle/16/0/0"},
                              {"BM_FlexibleCycle/16/2/3", "BM_FlexibleCycle/16/0/0"},
                              {"BM_FlexibleCycle/16/3/0", "BM_FlexibleCycle/16/0/0"},
                              {"BM_FlexibleCycle/16/3/2", "BM_FlexibleCycle/16/0/0"}},
                             ipmc::RatioClock::kCpu);
}
