// Google Benchmark console output followed by each benchmark's wall time
// relative to a baseline benchmark of the same run.
#pragma once

#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace ipmc {

// Console output plus the CPU-time ratios to a baseline at the end.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) {
      if (run.run_type == Run::RT_Aggregate && run.aggregate_name != "median") continue;
      // Seconds per iteration, whatever unit the benchmark reports in.
      time_[run.run_name.function_name] =
          run.GetAdjustedRealTime() / benchmark::GetTimeUnitMultiplier(run.time_unit);
    }
  }
  void PrintRatios(const std::string& baseline) const {
    const auto bare = time_.find(baseline);
    if (bare == time_.end()) return;
    std::printf("\nWall time relative to %s:\n", baseline.c_str());
    for (const auto& [name, ns] : time_) {
      std::printf("  %-30s %6.3f\n", name.c_str(), ns / bare->second);
    }
  }

 private:
  std::map<std::string, double> time_;
};

// Runs the registered benchmarks and prints the ratios to each baseline.
inline int RunWithRatios(int argc, char** argv, const std::vector<std::string>& baselines) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  for (const std::string& baseline : baselines) reporter.PrintRatios(baseline);
  benchmark::Shutdown();
  return 0;
}

inline int RunWithRatios(int argc, char** argv, const std::string& baseline) {
  return RunWithRatios(argc, argv, std::vector<std::string>{baseline});
}

}  // namespace ipmc
