// Cost of the IPMC actuators (link models integrated by CVODE in
// mjcb_control): the paper's flagellum, clamped and free, with the drag
// alone and with the actuators driven by a 3 V, 1 Hz sine updated at
// 1 kHz, in one run. Ratios are printed against the clamped drag-only step.
// Then the peak memory after a 20 s and after a 200 s actuated chirp: the
// Oustaloup state has a fixed size, so the peak must not grow.
//
//   ./build/bench/actuator_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include <sys/resource.h>

#include <cstdio>

#include "bench/ratio_reporter.h"
#include "sim/runs/bench_run.h"
#include "ipmc_swim/ipmc_swim.h"
#include "sim/core/model_generator.h"
#include "sim/core/simulation.h"
#include "sim/base/numbers.h"

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
      volts.assign(3, 3.0 * std::sin(ipmc::kTwoPi * d->time));
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

long PeakMemory_kB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

// Runs the paper's chirp (3 V, 0.1 Hz up) for `duration_s` on the clamped
// flagellum without keeping samples.
void RunChirp(double duration_s) {
  Simulation sim(LoadModelString(FlagellumXml(true, true)), "clamped flagellum");
  BenchSignal chirp;
  chirp.kind = BenchSignal::Kind::kChirp;
  chirp.duration_s = duration_s;
  chirp.end_Hz = 0.1 + (200.0 - 0.1) * duration_s / 200.0;
  RunBench(sim, chirp, duration_s);
}

void ReportMemoryGrowth() {
  RunChirp(20.0);
  const long short_kB = PeakMemory_kB();
  RunChirp(200.0);
  const long long_kB = PeakMemory_kB();
  std::printf("\npeak memory: %ld kB after a 20 s chirp, %ld kB after a 200 s one (ratio %.3f)\n",
              short_kB, long_kB, static_cast<double>(long_kB) / short_kB);
}

}  // namespace
}  // namespace ipmc

int main(int argc, char** argv) {
  const int status = ipmc::RunWithRatios(argc, argv, "BM_ClampedDragOnly");
  if (status == 0) ipmc::ReportMemoryGrowth();
  return status;
}
