#include "sim/cli/run_print.h"

#include <cstdio>
#include <string>

namespace ipmc {

void PrintSwimMetrics(const SwimMetrics& swim) {
  std::printf("%5s %14s %14s %14s %14s\n", "cycle", "com_along_mm", "com_across_mm",
              "head_along_mm", "head_across_mm");
  for (size_t k = 0; k < swim.per_cycle.size(); ++k) {
    const Displacement_mm& c = swim.per_cycle[k];
    std::printf("%5zu %14.6g %14.6g %14.6g %14.6g\n", k + 1, c.com_along, c.com_across,
                c.head_along, c.head_across);
  }
  std::printf("mean speed along the swimming axis: %.6g mm/s\n", swim.mean_speed_along_mm_s);
  std::printf("Reynolds number: %.3g (peak lateral tip speed x width), %.3g (mean speed x length)\n",
              swim.reynolds_tip, swim.reynolds_swim);
  for (const std::string& warning : swim.warnings) {
    std::fprintf(stderr, "warning: %s\n", warning.c_str());
  }
}

void PrintWritten(const std::string& dir, const RunFileFormats& formats) {
  std::string extra;
  if (formats.mat) extra += std::string(", ") + kRunMatFile;
  if (formats.hdf5) extra += std::string(", ") + kRunHdf5File;
  std::printf("wrote %s/timeseries.csv, states.csv%s and summary.json\n", dir.c_str(),
              extra.c_str());
}

}  // namespace ipmc
