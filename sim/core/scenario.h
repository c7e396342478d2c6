// A scenario file (TOML) describes one closed-loop run: model, actuation,
// controller, waveform, duration, fluid and outputs. Every key is
// optional except model; unknown keys, wrong types and out-of-range values
// are errors naming the file, key and line. The key table with types,
// units, ranges and defaults is sim/core/scenario_keys.h (`ipmc-swim keys`,
// docs/SCENARIO_KEYS.md); in short:
//
//   model = "models/flagellum3.xml"    # relative to the scenario file
//   link_lengths_mm = [8, 10, 12]      # instead: the generated flagellum with
//                                      # these links (1-20, > 0) and the
//                                      # generator's other defaults; wins
//                                      # over model
//   segments_per_link = 4              # rigid sub-segments per link, [1, 31] on
//                                      # three links (MuJoCo's nesting limit);
//                                      # also generates the flagellum (links
//                                      # of 10 mm unless link_lengths_mm)
//   plants = "uniform"                 # uniform | table2, over the model's
//                                      # ipmc_plants (plugin/actuators/ipmc_actuators.h)
//   actuation = "distributed"          # distributed | single
//   dynamics = "stokes"                # inertial | stokes, over the model's
//                                      # ipmc_dynamics (plugin/fluid/stokes_step.h)
//   hinge_damping_scale = 1.0          # times the joints' damping; >= 0
//   cycles = 3                         # >= 1
//   timestep_s = 5e-4                  # overrides the model's step; (0, 1e-3]
//   [controller]
//   kind = "pid"                       # pid | fractional
//   sample_rate_Hz = 1000.0            # > 0, a whole number of steps
//   v_max_V = 6.0                      # > 0
//   clamp = true
//   kp = 8.12; ki = 53.36; kd = 0.61; derivative_filter_s = 0.0     # pid
//   gain = 15.62; order = 0.62; oustaloup_n = 4; band_rad_s = [1e-3, 1e2]  # fractional
//   realisation = "oustaloup"          # fractional: oustaloup (K / s^lambda by
//                                      # Oustaloup on the band) | eq15 (the
//                                      # paper's printed eq. 15; no gain,
//                                      # order, oustaloup_n or band_rad_s)
//   [waveform]
//   kind = "polynomial"                # polynomial | fractional
//   c0_um = 0.0; c1_um_per_mm = 200.0; c2_um_per_mm2 = 0.0
//   c_um = 0.0; alpha = 0.5
//   frequency_Hz = 0.01; wavelength_mm = 32.0
//   start_ramp_cycles = 0.25           # references fade in over this; [0, cycles]
//   [fluid]
//   viscosity_Pa_s = 1e-3              # overrides the model's; > 0
//   rft_coefficients = "lighthill"     # gray_hancock | lighthill, over the model's
//   rft_wavelength_mm = 32.0           # in the coefficients; default the wave's
//   wall_gap_mm = 2.0                  # a wall below the strip's edge; > 0
//   model = "stokeslets"               # rft | stokeslets (docs/FLUIDS.md)
//   [metrics]
//   from_cycle = 2                     # IAE/ITAE, clamp share, mean speed and
//                                      # powers over cycles 2..cycles; [1, cycles];
//                                      # default: the first after the start ramp
//   [output]
//   dir = "out/paper"                  # relative to the working directory
//   samples_per_cycle = 200
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "controllers/fractional_integrator.h"
#include "controllers/pid.h"
#include "plugin/actuators/ipmc_actuators.h"
#include "sim/core/electrical.h"
#include "sim/core/strip_keys.h"
#include "sim/core/waveform.h"

namespace ipmc {

enum class ControllerKind { kPid, kFractional };

struct ScenarioConfig {
  std::string source;       // the scenario file, for messages
  std::string model_path;   // resolved against the scenario's directory
  std::vector<double> link_lengths_mm;  // non-empty: generate the model instead
  int segments_per_link = 0;            // > 0: generate the model instead
  std::optional<PlantAssignment> plants;  // over the model's ipmc_plants
  StripConfig strip;  // [strip]: any key generates the model
  PlantConfig plant;  // [plant]: likewise
  std::string actuation = "distributed";
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
  // Over the model's ipmc_rft_coefficients: gray_hancock or lighthill.
  std::optional<std::string> rft_coefficients;
  // The wavelength in those coefficients; waveform.wavelength_mm if unset.
  std::optional<double> rft_wavelength_mm;
  // A no-slip wall this far below the strip's lower edge (near-wall RFT,
  // or the Stokeslets' image system).
  std::optional<double> wall_gap_mm;
  // The fluid model, "rft", "stokeslets" or "ribbon", and the Stokeslets' points
  // (unset: the defaults of plugin/fluid/fluid_model.h).
  std::string fluid_model = "rft";
  int stokeslet_width_points = 1;  // across the strip's width; 1: the centreline
  std::optional<double> stokeslet_points_per_mm, stokeslet_blob_mm;
  double stokeslet_shape_tolerance_rad = 1e-3;
  int ribbon_modes = 8;  // slender-ribbon theory's Legendre modes (plugin/fluid/ribbon_fluid.h)
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

// Parses and validates; throws InputError (plugin/base/error.h, a
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
