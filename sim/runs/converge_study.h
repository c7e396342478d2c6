// ipmc-swim converge: is a scenario's swim converged in its numerical
// settings? The scenario's gait run at
//
//   segments  segments_per_link n = 1, 2, 4, ... up to max_segments
//             (rigid links to a flexible strip; the swim is second order
//             in 1 / n, docs/DYNAMICS.md), extrapolated by Richardson from
//             the two finest: s_N + (s_N - s_(N/2)) / 3;
//   timestep  the scenario's step h and h / 2, h / 4, ... (halvings
//             times); first order in h with the inertial dynamics, with
//             the Stokes step the order p the three finest runs show,
//             within [1, 2] (1 with two runs): s_h + (s_h - s_(2h)) / (2^p - 1);
//   plates    the flat-plate fluid at k = 1 .. max_plates_k force points
//             across the width, whose error is linear in 1 / k
//             (docs/FLUIDS.md, "Flat plates"): the line through the two
//             finest to 1 / k = 0, (k s_k - (k - 1) s_(k-1));
//
// each study from the scenario as it is, in parallel (FanOut,
// sim/core/fan_out.h). The reference's own uncertainty is how far it
// moves when the finest run is left out (the extrapolation from the next
// two), or, with two runs only, the extrapolation's own correction. The
// swim is the last cycle's centre-of-mass displacement [mm], the fluid
// power its mean over that cycle [W]; the cost the wall time per
// simulated second on the threads the study ran with.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "sim/io/option_table.h"

namespace ipmc {

struct ConvergeCommand {
  std::string scenario;
  std::string out;          // "": no files
  int max_segments = 8;     // the segments study's finest n, >= 2
  int halvings = 2;         // the timestep study's, >= 1
  int max_plates_k = 3;     // the plates study's finest k; 0: none, else >= 2
  int cycles = 2;           // the runs' wave periods
  int jobs = 2;             // threads
};
const OptionTable<ConvergeCommand>& ConvergeOptions();

// The largest relative error that counts as converged.
constexpr double kConvergedError = 0.01;

struct ConvergeRun {
  std::string study;    // "scenario", "segments", "timestep", "plates"
  std::string setting;  // "segments_per_link=4"
  double resolution = 0.0;  // n, 1 / h [1/s], k; 0 for the scenario
  double swim_mm = 0.0;
  double fluid_power_W = 0.0;
  double cost_s_per_s = 0.0;  // wall time per simulated second
  int warnings = 0;           // the run's failed checks (run_warnings.h)
};

struct ConvergeReference {
  double value = 0.0;
  double uncertainty = 0.0;  // absolute
};

struct ConvergeStudy {
  std::string name;
  std::vector<ConvergeRun> runs;  // coarse to fine
  ConvergeReference swim, fluid_power;
};

struct ConvergeOutcome {
  ConvergeRun scenario;  // the scenario as it is
  std::vector<ConvergeStudy> studies;
  std::string table_path;  // OUT/converge.csv, "" without out
};

// Runs the studies and writes OUT/converge.csv (study, setting, the swim
// and fluid power with their errors against the study's reference, the
// cost, the warnings). Throws FieldError for a bad option, InputError for
// a bad scenario, std::runtime_error for a failed run (nothing written).
ConvergeOutcome RunConvergeCommand(const ConvergeCommand& command);

// The relative error of `value` against the reference.
double ConvergeError(double value, const ConvergeReference& reference);

}  // namespace ipmc
