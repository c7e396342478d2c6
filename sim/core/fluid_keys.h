// The fluid as scenario keys: [fluid], the viscosity and the RFT
// coefficients over the model's, a wall, the fluid model
// (plugin/fluid/fluid_model.h) and each model's resolution; and the
// scenario's fluid part those keys set.
#pragma once

#include <optional>
#include <vector>

#include "plugin/fluid/rft_drag.h"
#include "sim/core/choice_table.h"
#include "sim/core/scenario_keys.h"

namespace ipmc {

enum class FluidModel { kRft, kStokeslets, kRibbon, kPlates };

inline constexpr ChoiceName<FluidModel> kFluidModelNames[] = {
    {"rft", FluidModel::kRft},
    {"stokeslets", FluidModel::kStokeslets},
    {"ribbon", FluidModel::kRibbon},
    {"plates", FluidModel::kPlates},
};

// The regularized Stokeslets' points (fluid.model = "stokeslets"; unset:
// the defaults of plugin/fluid/fluid_model.h).
struct StokesletScenario {
  int width_points = 1;  // across the strip's width; 1: the centreline
  std::optional<double> points_per_mm, blob_mm;
  double shape_tolerance_rad = 1e-3;
};

// Slender-ribbon theory's Legendre modes (plugin/fluid/ribbon_fluid.h).
struct RibbonScenario {
  int modes = 8;
};

// The flat plates' resolution (plugin/fluid/plate_fluid.h).
struct PlateScenario {
  int points_across = 4;
  int quadrature_refinement = 4;
  bool richardson = true;
};

// [fluid]: every key is a single-key range the key table checks; the
// combinations a model file decides (a wall with the coefficients, a wall
// for a free-space model) are refused where the fluid is built
// (ScenarioFluidOverrides, sim/core/scenario_simulation.h).
struct FluidScenario {
  FluidModel model = FluidModel::kRft;
  std::optional<double> viscosity_Pa_s;  // over the model's
  // Over the model's ipmc_rft_coefficients.
  std::optional<CoefficientModel> rft_coefficients;
  // The wavelength in those coefficients; waveform.wavelength_mm if unset.
  std::optional<double> rft_wavelength_mm;
  // A no-slip wall this far below the strip's lower edge (near-wall RFT,
  // or the Stokeslets' image system).
  std::optional<double> wall_gap_mm;
  StokesletScenario stokeslets;
  RibbonScenario ribbon;
  PlateScenario plates;
};

// The [fluid] keys of the key table, in its order.
std::vector<KeySpec> FluidKeys();

}  // namespace ipmc
