// Wall time of the paper's closed-loop run (scenarios/paper.toml: three
// 100 s cycles) against the simulated time it covers (realtime factor) and
// against the drag-only swimmer stepped over the same simulated time with
// the same step, in one run. Also the cost of one coupled step of the free
// swimmer with n = 1, 2, 4, 8 rigid sub-segments per link (20 000 steps,
// voltages changed every 1 ms as by the controllers), so its wall time
// relative to the drag-only run is the cost per step against n.
//
//   ./build/bench/closed_loop_bench
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>

#include "bench/ratio_reporter.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/core/model_generator.h"
#include "ipmc_swim/ipmc_swim.h"
#include "sim/core/scenario.h"
#include "sim/core/simulation.h"
#include "sim/io/numbers.h"

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

// 20 000 coupled steps of the free swimmer with `segments` sub-segments
// per link, a 3 V sine at 1 Hz on every link updated every 1 ms. The step
// is the same for every n, 5e-4 s / 8^2 (what n = 8 needs: the hinge modes
// go as n^2), so the ratios are the cost of one step against n; a
// simulated second costs n^2 times more steps on top.
void BM_CoupledSteps(benchmark::State& state, int segments) {
  FlagellumSpec spec;
  spec.segments_per_link = segments;
  spec.timestep_s = 5e-4 / 64;
  const long steps_per_sample = std::lround(1e-3 / spec.timestep_s);
  constexpr long kSteps = 20000;
  for (auto _ : state) {
    Simulation sim(LoadModelString(GenerateFlagellumMjcf(spec)), "flexible flagellum");
    double volts[3] = {0, 0, 0};
    for (long i = 0; i < kSteps; ++i) {
      if (i % steps_per_sample == 0) {
        const double v = 3.0 * std::sin(ipmc::kTwoPi * sim.data()->time);
        for (double& volt : volts) volt = v;
        SetVoltages(sim.data(), volts, 3);
      }
      sim.Step();
    }
  }
  state.SetItemsProcessed(kSteps * state.iterations());
}

// The drag-only swimmer (rigid links) over the same 20 000 steps.
void BM_DragOnlySteps(benchmark::State& state) {
  FlagellumSpec spec;
  spec.ipmc_actuators = false;
  spec.timestep_s = 5e-4 / 64;
  for (auto _ : state) {
    Simulation sim(LoadModelString(GenerateFlagellumMjcf(spec)), "drag-only flagellum");
    sim.data()->qvel[0] = 1e-4;
    for (long i = 0; i < 20000; ++i) sim.Step();
  }
  state.SetItemsProcessed(20000 * state.iterations());
}

BENCHMARK(BM_PaperScenario)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK(BM_DragOnlySwimmer)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK(BM_DragOnlySteps)->Repetitions(5)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_CoupledSteps, segments_1, 1)->Repetitions(5)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_CoupledSteps, segments_2, 2)->Repetitions(5)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_CoupledSteps, segments_4, 4)->Repetitions(5)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_CoupledSteps, segments_8, 8)->Repetitions(5)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace ipmc

int main(int argc, char** argv) {
  return ipmc::RunWithRatios(argc, argv,
                             std::vector<std::string>{"BM_DragOnlySwimmer", "BM_DragOnlySteps"});
}
