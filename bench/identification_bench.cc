// Identification cost against the experiment it analyses, in one run: the
// simulated bench chirp of section 4.1 (3 V, 0.1-200 Hz, 200 s at 1 kHz,
// link 1 of the clamped flagellum), Welch plus Levy with the full alpha
// sweep on that record, and the PID tuning of eq. 11 (Nelder-Mead, five
// starts, 2 s horizon).
//
//   ./build/bench/identification_bench
#include <benchmark/benchmark.h>

#include "bench/ratio_reporter.h"
#include "sim/core/data_paths.h"
#include "sim/runs/bench_run.h"
#include "sim/identify/controller_design.h"
#include "sim/identify/levy.h"
#include "sim/core/simulation.h"
#include "sim/identify/welch.h"

namespace ipmc {
namespace {

// The chirp of `ipmc-swim bench --signal chirp` on the shipped clamped model.
BenchRecord PaperChirpRecord() {
  const std::string model = ModelsDir() + "/flagellum3_clamped.xml";
  Simulation sim(LoadModelFile(model), model);
  BenchSignal chirp;
  chirp.kind = BenchSignal::Kind::kChirp;
  return RunBench(sim, chirp);
}

void BM_SimulateBenchChirp(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(PaperChirpRecord());
}

void BM_IdentifyOneLink(benchmark::State& state) {
  const BenchRecord record = PaperChirpRecord();
  for (auto _ : state) {
    const FrequencyResponseEstimate estimate =
        EstimateFrequencyResponse(record.voltage_V[0], record.relative_mm[0], WelchOptions());
    benchmark::DoNotOptimize(IdentifyLinkModels(estimate));
  }
}

void BM_TunePid(benchmark::State& state) {
  const StateSpace plant = AccurateLinkPlant(PaperLinkParams(3, IpmcModelKind::kG1));
  for (auto _ : state) benchmark::DoNotOptimize(TunePid(plant));
}

BENCHMARK(BM_SimulateBenchChirp)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK(BM_IdentifyOneLink)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_TunePid)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace
}  // namespace ipmc

int main(int argc, char** argv) {
  return ipmc::RunWithRatios(argc, argv, "BM_SimulateBenchChirp");
}
