// The fluid as scenario keys: [fluid], the viscosity and the RFT
// coefficients over the model's, a wall, the fluid model and one key per
// parameter of each model, from the models' registry
// (plugin/fluid/fluid_model.h); and the scenario's fluid part those keys
// set.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ipmc_swim/fields.h"
#include "sim/core/scenario_keys.h"

namespace ipmc {

// The key that chooses the fluid model, and the selector of its parameters' keys.
constexpr char kFluidModelKey[] = "fluid.model";

// [fluid]: every key is a single-key range the key table checks; the
// combinations a model file decides (a wall with the coefficients, a wall
// for a free-space model) are refused where the fluid is built
// (ScenarioFluidOverrides, sim/core/scenario_simulation.h).
struct FluidScenario {
  // The fluid model (FluidModelDescriptions(), ipmc_swim/fields.h) over the
  // model file's ipmc_fluid_model.
  std::optional<std::string> model;
  std::optional<double> viscosity_Pa_s;  // over the model's
  // Over the model's ipmc_rft_coefficients.
  std::optional<CoefficientModel> rft_coefficients;
  // The wavelength in those coefficients; waveform.wavelength_mm if unset.
  std::optional<double> rft_wavelength_mm;
  // A no-slip wall this far below the strip's lower edge (near-wall RFT,
  // or the Stokeslets' image system).
  std::optional<double> wall_gap_mm;
  // The chosen model's parameters the scenario sets (fluid.<key>,
  // FluidParameter), by key, in the key's unit.
  std::map<std::string, double> parameters;
};

// The [fluid] keys of the key table, in its order.
std::vector<KeySpec> FluidKeys();

}  // namespace ipmc
