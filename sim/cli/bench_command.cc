#include "sim/cli/bench_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sim/cli/run_watch.h"

namespace ipmc {

void AddBenchCommand(CLI::App& app, BenchArgs& args) {
  AddTableCommand(app, BenchOptions(), args)->get_option("--out")->required();
}

int RunBenchCommandLine(const BenchArgs& args) {
  if (!args.Chosen()) return -1;
  const BenchCommand& command = args.spec;
  RunWatch watch("bench", command.bench.duration_s);
  const BenchRecord record = TranslatingFieldErrors(BenchOptions(), [&] {
    return RunBenchCommand(command, [&](double t_s) { watch.At(t_s); });
  });
  watch.Finish();
  std::printf("%zu samples at %g Hz written to %s\n", record.t_s.size(),
              command.bench.sample_rate_Hz, command.out.c_str());
  for (size_t q = 0; q < record.relative_mm.size(); ++q) {
    double peak = 0.0;
    for (double value : record.relative_mm[q]) peak = std::max(peak, std::abs(value));
    std::printf("link %zu: peak relative tip deflection %.6g mm\n", q + 1, peak);
  }
  return 0;
}

}  // namespace ipmc
