// A scenario file (TOML) describes one closed-loop run: model, actuation,
// controller, waveform, duration, fluid, metrics and outputs. Every key is
// optional except model (or a generated flagellum); unknown keys, wrong
// types and out-of-range values are errors naming the file, key and line.
// The keys, with their types, units, ranges, defaults and meanings, are
// the key table of sim/core/scenario_keys.h, and only there: `ipmc-swim
// keys` prints it and docs/SCENARIO_KEYS.md is its Markdown form. E.g.
//
//   model = "../models/flagellum3.xml"   # relative to the scenario file
//   cycles = 3
//   [controller]
//   kind = "pid"
//   [waveform]
//   frequency_Hz = 0.01
//   [output]
//   dir = "out/paper"                    # relative to the working directory
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "ipmc_swim/fields.h"
#include "sim/core/choice_table.h"
#include "sim/core/controller_keys.h"
#include "sim/core/drive_keys.h"
#include "sim/core/electrical.h"
#include "sim/core/fluid_keys.h"
#include "sim/core/strip_keys.h"
#include "sim/core/waveform.h"

namespace ipmc {

// The texts of the scenario's choices, each parsed once by its key's
// reader (sim/core/scenario_keys.cc): a new value is one line here (the
// controller's and the fluid model's beside their parts,
// sim/core/controller_keys.h and sim/core/fluid_keys.h).
inline constexpr ChoiceName<Actuation> kActuationNames[] = {
    {"distributed", Actuation::kDistributed},
    {"single", Actuation::kSingle},
};
inline constexpr ChoiceName<WaveformKind> kWaveformKindNames[] = {
    {"polynomial", WaveformKind::kPolynomial},
    {"fractional", WaveformKind::kFractional},
};
// fluid.rft_coefficients: the sets a scenario may choose over the model's.
inline constexpr ChoiceName<CoefficientModel> kRftCoefficientNames[] = {
    {"gray_hancock", CoefficientModel::kGrayHancock},
    {"lighthill", CoefficientModel::kLighthill},
    {"ribbon", CoefficientModel::kRibbon},
    {"ribbon_fitted", CoefficientModel::kRibbonFitted},
};

// How long the run is and how it steps. The time step's fit to the
// controller's sample rate (a whole number of steps per sample) is checked
// by the scenario reader (sim/core/scenario.cc), which sees both parts.
struct RunScenario {
  int cycles = 3;
  std::optional<double> timestep_s;  // over the model's
  // Not a file key: the command line's --allow-long, which lifts the run
  // size limits of sim/core/step_count.h.
  bool allow_long = false;
};

// What the run's summary metrics cover and add.
struct MetricsScenario {
  // The first cycle (1-based, <= cycles, which its key checks) of the
  // run's link metrics, mean speed and mean powers; the per-cycle tables
  // keep every cycle. 0 (the default): the first cycle after the start
  // ramp (MetricsFromCycle, sim/runs/closed_loop_run.h).
  int from_cycle = 0;
  // [electrical]: the links' electrical power (sim/core/electrical.h); off
  // by default.
  ElectricalConfig electrical;
};

// [output]: what the run writes.
struct OutputScenario {
  std::string dir;  // empty: no files
  int samples_per_cycle = 200;
};

// A scenario in its parts, each defined beside the keys that set it.
struct ScenarioConfig {
  std::string source;  // the scenario file, for messages
  ModelScenario model;  // sim/core/strip_keys.h
  Actuation actuation = Actuation::kDistributed;
  RunScenario run;
  ControllerScenario controller;  // sim/core/controller_keys.h
  WaveformScenario waveform;      // sim/core/waveform.h
  DriveScenario drive;            // sim/core/drive_keys.h
  FluidScenario fluid;            // sim/core/fluid_keys.h
  MetricsScenario metrics;
  OutputScenario output;
  // What the reader decided where keys competed, one line each: a model
  // file and keys that generate the flagellum (the generated one runs).
  std::vector<std::string> notes;
};

// Parses and validates; throws InputError (sim/base/error.h, a
// std::runtime_error) "FILE:LINE: key: reason" that carries the file, line,
// dotted key, what is wrong (InputProblem) and the allowed range.
ScenarioConfig LoadScenario(const std::string& path);
// The same from TOML text; `source` names it in messages and resolves
// relative model paths.
ScenarioConfig ParseScenario(const std::string& toml_text, const std::string& source);

// The scenario as TOML that ParseScenario reads back to the same run: every
// key of the chosen kinds with its value, defaults filled in, and the model
// as an absolute path. Left out: output.dir (where results go is no part of
// the result) and timestep_s, plants and fluid.viscosity_Pa_s where the
// scenario takes them from the model file (whose bytes the run's
// provenance pins by their hash).
std::string ResolvedScenarioToml(const ScenarioConfig& config);

}  // namespace ipmc
