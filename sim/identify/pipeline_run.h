// `pipeline`: the bench chirp of section 4.1 on the simulated clamped
// flagellum, then Welch, Levy and both designs of section 5.2 for link 3
// on its identified G1, as a Markdown report (sim/cli/pipeline_command.h
// describes the experiment and its options).
#pragma once

#include <string>
#include <vector>

#include "sim/io/option_table.h"

namespace ipmc {

struct PipelineCommand {
  std::string model;  // "": models/flagellum3_clamped.xml
  std::string drive = "each";  // each | first
  double duration_s = 200.0;
  double amplitude_V = 3.0;
  double start_Hz = 0.1;
  double end_Hz = 200.0;
  int repeats = 1;
  double noise_mm = 0.0;
  unsigned seed = 1;
  std::vector<double> band_rad_s = {0.2, 50.0};
  double crossover_rad_s = 5.0;
  double phase_margin_deg = 75.0;
  double horizon_s = 2.0;
  std::string out;  // "": no files
};

const OptionTable<PipelineCommand>& PipelineOptions();

// Validates (FieldError naming the field), runs the benches (in parallel
// threads with drive each), identifies, designs and returns the report;
// with `out`, writes OUT/report.md and OUT/response_link<q>.csv.
std::string RunPipelineCommand(const PipelineCommand& command);

}  // namespace ipmc
