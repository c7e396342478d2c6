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

#include "controllers/fractional_integrator.h"
#include "controllers/pid.h"
#include "plugin/actuators/ipmc_actuators.h"
#include "plugin/fluid/rft_drag.h"
#include "sim/core/choice_table.h"
#include "sim/core/electrical.h"
#include "sim/core/strip_keys.h"
#include "sim/core/waveform.h"

namespace ipmc {

enum class ControllerKind { kPid, kFractional };
enum class FluidModel { kRft, kStokeslets, kRibbon, kPlates };

// The texts of the scenario's choices, each parsed once by its key's
// reader (sim/core/scenario_keys.cc): a new value is one line here.
inline constexpr ChoiceName<ControllerKind> kControllerKindNames[] = {
    {"pid", ControllerKind::kPid},
    {"fractional", ControllerKind::kFractional},
};
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
};
inline constexpr ChoiceName<FluidModel> kFluidModelNames[] = {
    {"rft", FluidModel::kRft},
    {"stokeslets", FluidModel::kStokeslets},
    {"ribbon", FluidModel::kRibbon},
    {"plates", FluidModel::kPlates},
};

struct ScenarioConfig {
  std::string source;       // the scenario file, for messages
  std::string model_path;   // resolved against the scenario's directory
  std::vector<double> link_lengths_mm;  // non-empty: generate the model instead
  int segments_per_link = 0;            // > 0: generate the model instead
  std::optional<PlantAssignment> plants;  // over the model's ipmc_plants
  StripConfig strip;  // [strip]: any key generates the model
  PlantConfig plant;  // [plant]: likewise
  Actuation actuation = Actuation::kDistributed;
  std::optional<Dynamics> dynamics;       // over the model's ipmc_dynamics
  double hinge_damping_scale = 1.0;       // times every joint's damping
  int cycles = 3;
  std::optional<double> timestep_s;
  ControllerKind controller = ControllerKind::kPid;
  double sample_rate_Hz = 1000.0;
  PidController::Config pid;                    // sample period, clamp set from the fields above
  FractionalIntegrator::Config fractional;
  // Per-link gains, one per link in order (empty: every link takes the one
  // above): what an optimisation that retunes each design's controllers
  // sets (docs/OPTIMIZE.md).
  struct LinkGains {
    std::vector<double> kp, ki, kd;  // PID [V/mm], [V/(mm s)], [V s/mm]
    std::vector<double> gain, order;  // fractional [V/(mm s^lambda)], lambda
  } link_gains;
  WaveformConfig waveform;
  // The references are multiplied by (1 - cos(pi t / T_r)) / 2 for
  // t < T_r = start_ramp_cycles / f, so the run starts without a jump.
  double start_ramp_cycles = 0.25;
  std::optional<double> viscosity_Pa_s;
  // Over the model's ipmc_rft_coefficients.
  std::optional<CoefficientModel> rft_coefficients;
  // The wavelength in those coefficients; waveform.wavelength_mm if unset.
  std::optional<double> rft_wavelength_mm;
  // A no-slip wall this far below the strip's lower edge (near-wall RFT,
  // or the Stokeslets' image system).
  std::optional<double> wall_gap_mm;
  // The fluid model and the Stokeslets' points (unset: the defaults of
  // plugin/fluid/fluid_model.h).
  FluidModel fluid_model = FluidModel::kRft;
  int stokeslet_width_points = 1;  // across the strip's width; 1: the centreline
  std::optional<double> stokeslet_points_per_mm, stokeslet_blob_mm;
  double stokeslet_shape_tolerance_rad = 1e-3;
  int ribbon_modes = 8;  // slender-ribbon theory's Legendre modes (plugin/fluid/ribbon_fluid.h)
  // The plates' resolution (plugin/fluid/plate_fluid.h).
  int plate_points_across = 4;
  int plate_quadrature_refinement = 4;
  bool plate_richardson = true;
  // The first cycle (1-based, <= cycles) of the run's link metrics, mean
  // speed and mean powers; the per-cycle tables keep every cycle. 0 (the
  // default): the first cycle after the start ramp (MetricsFromCycle,
  // sim/runs/closed_loop_run.h).
  int metrics_from_cycle = 0;
  // The links' electrical power (sim/core/electrical.h); off by default.
  ElectricalConfig electrical;
  std::string output_dir;   // empty: no files
  int samples_per_cycle = 200;
  // Not a file key: the command line's --allow-long, which lifts the run
  // size limits of sim/core/step_count.h.
  bool allow_long_run = false;

  bool GeneratesModel() const {
    return !link_lengths_mm.empty() || segments_per_link > 0 || strip.Any() || plant.Any();
  }
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
