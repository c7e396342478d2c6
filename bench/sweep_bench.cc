// Sweep throughput with one and with two worker threads, in one run, on
// an 8-point sweep of short closed-loop runs (the paper's scenario at 0.03
// to 0.065 Hz, two cycles): runs per minute and the parallel efficiency
// (time with 1 job / (2 x time with 2 jobs)); and the cost of the journal
// (one record, written and synced to the disk as the sweep command does
// after every point). bench/slurm_overhead.sh measures a resume and the
// Slurm route.
//
//   ./build/bench/sweep_bench
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>
#include <vector>

#include "bench/ratio_reporter.h"
#include "sim/core/data_paths.h"
#include "sim/batch/journal.h"
#include "sim/batch/sweep.h"

namespace ipmc {
namespace {

SweepPlan EightPointSweep() {
  const std::string base = ScenariosDir() + "/paper.toml";
  return ParseSweep("base = \"" + base +
                        "\"\n[set]\ncycles = 2\n[grid]\n\"waveform.frequency_Hz\" = "
                        "[0.03, 0.035, 0.04, 0.045, 0.05, 0.055, 0.06, 0.065]\n",
                    "eight-point sweep");
}

void RunWithJobs(benchmark::State& state, int jobs) {
  const SweepPlan plan = EightPointSweep();
  SweepOptions options;
  options.jobs = jobs;
  long runs = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(RunSweep(plan, options));
    runs += static_cast<long>(plan.points.size());
  }
  state.counters["runs_per_minute"] =
      benchmark::Counter(60.0 * runs, benchmark::Counter::kIsRate);
}

void BM_SweepJobs1(benchmark::State& state) { RunWithJobs(state, 1); }
void BM_SweepJobs2(benchmark::State& state) { RunWithJobs(state, 2); }

// One journal record: a row of the 8-point sweep appended and synced to
// the disk (fdatasync), as the sweep command does after every point.
void BM_JournalRecord(benchmark::State& state) {
  const SweepPlan plan = EightPointSweep();
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "ipmc_sweep_bench.journal";
  std::filesystem::remove(path);
  SweepJournal journal(path.string(), plan);
  std::vector<std::string> row = SweepColumns(plan);  // a row of the table's width
  row[0] = "0";
  for (auto _ : state) journal.Record(row);
  std::filesystem::remove(path);
}

BENCHMARK(BM_SweepJobs1)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK(BM_SweepJobs2)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK(BM_JournalRecord)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace
}  // namespace ipmc

int main(int argc, char** argv) { return ipmc::RunWithRatios(argc, argv, "BM_SweepJobs1"); }
