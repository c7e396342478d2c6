// Wall time of the paper's closed-loop run (scenarios/paper.toml: three
// 100 s cycles) against the simulated time it covers (realtime factor) and
// against the drag-only swimmer stepped over the same simulated time with
// the same step, in one run.
//
//   ./build/bench/closed_loop_bench
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>

#include "bench/ratio_reporter.h"
#include "sim/closed_loop_run.h"
#include "sim/model_generator.h"
#include "sim/scenario.h"

namespace ipmc {
namespace {

const std::string kPaperScenario = std::string(IPMC_SWIM_MODELS_DIR) + "/../scenarios/paper.toml";

double SimulatedTime_s(const ScenarioConfig& scenario) {
  return scenario.cycles / std::abs(scenario.waveform.frequency_Hz);
}

void BM_PaperScenario(benchmark::State& state) {
  const ScenarioConfig scenario = LoadScenario(kPaperScenario);
  for (auto _ : state) benchmark::DoNotOptimize(RunScenario(scenario));
  state.counters["realtime_factor"] = benchmark::Counter(
      SimulatedTime_s(scenario) * state.iterations(), benchmark::Counter::kIsRate);
}

void BM_DragOnlySwimmer(benchmark::State& state) {
  const ScenarioConfig scenario = LoadScenario(kPaperScenario);
  FlagellumSpec spec;
  spec.ipmc_actuators = false;
  if (scenario.timestep_s) spec.timestep_s = *scenario.timestep_s;
  const long steps = std::lround(SimulatedTime_s(scenario) / spec.timestep_s);
  for (auto _ : state) {
    Simulation sim(LoadModelString(GenerateFlagellumMjcf(spec)), "drag-only flagellum");
    sim.data()->qvel[0] = 1e-4;
    for (long i = 0; i < steps; ++i) sim.Step();
  }
  state.counters["realtime_factor"] = benchmark::Counter(
      SimulatedTime_s(scenario) * state.iterations(), benchmark::Counter::kIsRate);
}

BENCHMARK(BM_PaperScenario)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK(BM_DragOnlySwimmer)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace
}  // namespace ipmc

int main(int argc, char** argv) { return ipmc::RunWithRatios(argc, argv, "BM_DragOnlySwimmer"); }
