// Google Benchmark console output followed by each benchmark's wall (or CPU) time
// relative to a baseline benchmark of the same run.
#pragma once

#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace ipmc {

// Which time the ratios compare: wall time, or the CPU time of the
// benchmark's thread (steadier on a loaded machine for one thread).
enum class RatioClock { kWall, kCpu };

// Console output plus time ratios at the end. A benchmark is named by its
// function and, if it has any, its arguments ("BM_Links/6"); with
// repetitions its median counts.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  explicit RatioReporter(RatioClock clock = RatioClock::kWall) : clock_(clock) {}

  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) {
      if (run.run_type == Run::RT_Aggregate && run.aggregate_name != "median") continue;
      std::string name = run.run_name.function_name;
      if (!run.run_name.args.empty()) name += "/" + run.run_name.args;
      // Seconds per iteration, whatever unit the benchmark reports in.
      const double time =
          clock_ == RatioClock::kCpu ? run.GetAdjustedCPUTime() : run.GetAdjustedRealTime();
      time_[name] = time / benchmark::GetTimeUnitMultiplier(run.time_unit);
    }
  }
  // Every benchmark against `baseline`.
  void PrintRatios(const std::string& baseline) const {
    const auto bare = time_.find(baseline);
    if (bare == time_.end()) return;
    std::printf("\n%s time relative to %s:\n", ClockName(), baseline.c_str());
    for (const auto& [name, seconds] : time_) {
      std::printf("  %-30s %6.3f\n", name.c_str(), seconds / bare->second);
    }
  }
  // Each (benchmark, baseline) pair that both ran.
  void PrintPairs(const std::vector<std::pair<std::string, std::string>>& pairs) const {
    bool header = false;
    for (const auto& [name, baseline] : pairs) {
      const auto a = time_.find(name), b = time_.find(baseline);
      if (a == time_.end() || b == time_.end()) continue;
      if (!header) std::printf("\n%s time relative to its own baseline:\n", ClockName());
      header = true;
      std::printf("  %-24s / %-24s %6.3f\n", name.c_str(), baseline.c_str(),
                  a->second / b->second);
    }
  }

 private:
  const char* ClockName() const { return clock_ == RatioClock::kCpu ? "CPU" : "Wall"; }

  RatioClock clock_;
  std::map<std::string, double> time_;
};

// Runs the registered benchmarks and prints the ratios to each baseline and
// of each pair.
inline int RunWithRatios(int argc, char** argv, const std::vector<std::string>& baselines,
                         const std::vector<std::pair<std::string, std::string>>& pairs = {},
                         RatioClock clock = RatioClock::kWall) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  RatioReporter reporter(clock);
  benchmark::RunSpecifiedBenchmarks(&reporter);
  for (const std::string& baseline : baselines) reporter.PrintRatios(baseline);
  reporter.PrintPairs(pairs);
  benchmark::Shutdown();
  return 0;
}

inline int RunWithRatios(int argc, char** argv, const std::string& baseline) {
  return RunWithRatios(argc, argv, std::vector<std::string>{baseline});
}

}  // namespace ipmc
