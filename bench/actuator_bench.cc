// Cost of the IPMC actuators (link models integrated by CVODE in
// mjcb_control): the paper's flagellum, clamped and free, with the drag
// alone and with the actuators driven by a 3 V, 1 Hz sine updated at
// 1 kHz, in one run. Ratios are printed against the clamped drag-only step.
//
//   ./build/bench/actuator_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include "bench/ratio_reporter.h"
#include "ipmc_swim/ipmc_swim.h"
#include "sim/model_generator.h"
#include "sim/simulation.h"

namespace ipmc {
namespace {

std::string FlagellumXml(bool clamped, bool actuators) {
  FlagellumSpec spec;
  spec.clamped = clamped;
  spec.ipmc_actuators = actuators;
  return GenerateFlagellumMjcf(spec);
}

void Run(benchmark::State& state, bool clamped, bool actuators) {
  ModelPtr m = LoadModelString(FlagellumXml(clamped, actuators));
  DataPtr d(mj_makeData(m.get()));
  Attach(m.get(), d.get());
  const int steps_per_sample = static_cast<int>(std::lround(1e-3 / m->opt.timestep));
  std::vector<double> volts(3, 0.0);
  long steps = 0;
  for (auto _ : state) {
    if (actuators && steps % steps_per_sample == 0) {
      volts.assign(3, 3.0 * std::sin(6.283185307179586 * d->time));
      SetVoltages(d.get(), volts.data(), 3);
    }
    mj_step(m.get(), d.get());
    ++steps;
  }
  state.SetItemsProcessed(steps);
  Detach(d.get());
}

void BM_ClampedDragOnly(benchmark::State& state) { Run(state, true, false); }
void BM_ClampedActuated(benchmark::State& state) { Run(state, true, true); }
void BM_FreeDragOnly(benchmark::State& state) { Run(state, false, false); }
void BM_FreeActuated(benchmark::State& state) { Run(state, false, true); }

BENCHMARK(BM_ClampedDragOnly)->MinTime(2.0);
BENCHMARK(BM_ClampedActuated)->MinTime(2.0);
BENCHMARK(BM_FreeDragOnly)->MinTime(2.0);
BENCHMARK(BM_FreeActuated)->MinTime(2.0);

}  // namespace
}  // namespace ipmc

int main(int argc, char** argv) { return ipmc::RunWithRatios(argc, argv, "BM_ClampedDragOnly"); }
