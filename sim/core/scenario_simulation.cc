#include "sim/core/scenario_simulation.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <stdexcept>

#include "ipmc_swim/ipmc_swim.h"
#include "plugin/coupling.h"
#include "plugin/fluid/stokeslet_fluid.h"
#include "sim/base/numbers.h"
#include "sim/core/hinge_damping.h"
#include "sim/core/model_generator.h"
#include "sim/core/sha256.h"
#include "sim/core/step_count.h"
#include "sim/io/files.h"

namespace ipmc {
namespace {

// "MODEL: has no RFT drag ...": the model, not the scenario key, lacks
// what `keys` (of the scenario `scenario_source`) need.
std::string NoDragMessage(const std::string& model, const std::string& scenario_source,
                          const std::string& keys) {
  return model + ": has no RFT drag (no <custom> numeric ipmc_rft_viscosity_Pa_s), which " +
         keys + " in " + scenario_source +
         " needs; add the model's drag fields (docs/LIBRARY.md) or leave " + keys + " out";
}

void OverrideViscosity(mjModel* m, double viscosity_Pa_s, const std::string& model,
                       const std::string& scenario_source) {
  const int id = mj_name2id(m, mjOBJ_NUMERIC, "ipmc_rft_viscosity_Pa_s");
  if (id < 0) {
    throw std::runtime_error(NoDragMessage(model, scenario_source, "fluid.viscosity_Pa_s"));
  }
  m->numeric_data[m->numeric_adr[id]] = viscosity_Pa_s;
}

// Throws naming the key that sets the points (the one the scenario gives:
// fluid.stokeslet_points_per_mm, else fluid.stokeslet_blob_mm, else
// fluid.stokeslet_width_points) if they are more than the machine holds or
// factors in reasonable time (CheckStokesletSize), before any step. Bad
// settings are left to the simulation, which names the model.
void CheckStokesletResolution(const ScenarioConfig& scenario, const mjModel* m,
                              const RftDragOverrides& overrides) {
  if (!overrides.stokeslets) return;
  std::unique_ptr<StokesletFluid> fluid;
  std::optional<RftDrag> drag;
  try {
    const std::optional<RftDragConfig> config = RftDragConfig::FromModel(m, overrides);
    if (!config) return;
    drag.emplace(m, *config);
    fluid = std::make_unique<StokesletFluid>(m, *drag, *overrides.stokeslets);  // builds no points
  } catch (const std::exception&) {
    return;
  }
  const StokesletSettings& settings = fluid->settings();
  double points = 0.0;  // as in SegmentPoints, without an int to overflow
  for (double length_m : fluid->rft().SegmentLengths_m()) {
    points += std::max(1.0, std::ceil(length_m / settings.spacing_m - 1e-9)) *
              settings.width_points;
  }
  std::string key = "fluid.model";
  if (scenario.fluid.stokeslets.points_per_mm) {
    key =
        "fluid.stokeslet_points_per_mm " + FormatShortest(*scenario.fluid.stokeslets.points_per_mm);
  } else if (scenario.fluid.stokeslets.blob_mm && scenario.fluid.stokeslets.width_points == 1) {
    key = "fluid.stokeslet_blob_mm " + FormatShortest(*scenario.fluid.stokeslets.blob_mm);
  } else if (scenario.fluid.stokeslets.width_points > 1) {
    key = "fluid.stokeslet_width_points " + std::to_string(scenario.fluid.stokeslets.width_points);
  }
  CheckStokesletSize(points, scenario.run.allow_long, scenario.source + ": " + key);
}

// The MJCF of the flagellum a scenario generates (ModelScenario::Generated()).
std::string GeneratedScenarioMjcf(const ScenarioConfig& scenario) {
  return GenerateFlagellumMjcf(ScenarioFlagellumSpec(scenario.model));
}

}  // namespace

std::string ScenarioModelSha256(const ScenarioConfig& scenario) {
  return Sha256Hex(scenario.model.Generated() ? GeneratedScenarioMjcf(scenario)
                                              : ReadTextFile(scenario.model.path, "model file"));
}

ModelPtr LoadScenarioModel(const ScenarioConfig& scenario, std::string* source,
                           std::vector<double>* physical_damping) {
  *source = scenario.model.path;
  ModelPtr model;
  if (!scenario.model.Generated()) {
    model = LoadModelFile(scenario.model.path);
  } else {
    *source = scenario.source + " (generated flagellum)";
    model = LoadModelString(GeneratedScenarioMjcf(scenario));
  }
  if (scenario.run.timestep_s) model->opt.timestep = *scenario.run.timestep_s;
  if (scenario.fluid.viscosity_Pa_s) {
    OverrideViscosity(model.get(), *scenario.fluid.viscosity_Pa_s, *source, scenario.source);
  }
  std::vector<double> damping =
      SetHingeDamping(model.get(), scenario.model.hinge_damping_scale, scenario.model.dynamics);
  if (physical_damping) *physical_damping = std::move(damping);
  return model;
}

std::unique_ptr<Simulation> LoadScenarioSimulation(const ScenarioConfig& scenario) {
  std::string source;
  IpmcActuatorsOverrides overrides;
  ModelPtr model = LoadScenarioModel(scenario, &source, &overrides.physical_damping);
  UseEulerWhereImplicitAddsNothing(model.get());  // as StepClosedLoop steps it
  overrides.plants = scenario.model.plants;
  overrides.dynamics = scenario.model.dynamics;
  const RftDragOverrides fluid = ScenarioFluidOverrides(scenario, model.get());
  // Before the simulation's first evaluation factors the Stokeslet matrix.
  CheckStokesletResolution(scenario, model.get(), fluid);
  auto sim = std::make_unique<Simulation>(std::move(model), source, overrides, fluid);
  const CouplingContext* coupling = FindCoupling(sim->data());
  if (!(coupling && coupling->drag)) {
    // Only the keys the scenario sets.
    std::string keys;
    const auto name = [&keys](bool set, const char* key) {
      if (set) keys += (keys.empty() ? "" : ", ") + std::string(key);
    };
    name(scenario.fluid.rft_coefficients.has_value(), "fluid.rft_coefficients");
    name(scenario.fluid.rft_wavelength_mm.has_value(), "fluid.rft_wavelength_mm");
    name(scenario.fluid.wall_gap_mm.has_value(), "fluid.wall_gap_mm");
    name(scenario.fluid.model != FluidModel::kRft, "fluid.model");
    if (!keys.empty()) {
      throw std::runtime_error(NoDragMessage(sim->source(), scenario.source, keys));
    }
  }
  return sim;
}

RftDragOverrides ScenarioFluidOverrides(const ScenarioConfig& scenario, const mjModel* m) {
  constexpr double kMmToM = 1e-3;
  RftDragOverrides fluid;
  if (scenario.fluid.rft_coefficients && scenario.fluid.wall_gap_mm) {
    throw std::runtime_error(scenario.source +
                             ": fluid.rft_coefficients and fluid.wall_gap_mm exclude each other "
                             "(near a wall RFT takes the near-wall coefficients)");
  }
  fluid.model = scenario.fluid.rft_coefficients;
  fluid.wavelength_m =
      scenario.fluid.rft_wavelength_mm.value_or(scenario.waveform.wavelength_mm) * kMmToM;
  if (scenario.fluid.wall_gap_mm) {
    fluid.wall_distance_m = *scenario.fluid.wall_gap_mm * kMmToM + 0.5 * StripWidth_m(m);
  }
  if (scenario.fluid.model == FluidModel::kStokeslets) {
    StokesletSettings stokeslets;
    if (scenario.fluid.stokeslets.blob_mm) {
      stokeslets.blob_m = *scenario.fluid.stokeslets.blob_mm * kMmToM;
    }
    if (scenario.fluid.stokeslets.points_per_mm) {
      stokeslets.spacing_m = kMmToM / *scenario.fluid.stokeslets.points_per_mm;
    }
    stokeslets.width_points = scenario.fluid.stokeslets.width_points;
    stokeslets.wall_distance_m = fluid.wall_distance_m;
    stokeslets.shape_tolerance_rad = scenario.fluid.stokeslets.shape_tolerance_rad;
    fluid.stokeslets = stokeslets;
  }
  if (scenario.fluid.model == FluidModel::kRibbon && scenario.fluid.wall_gap_mm) {
    throw std::runtime_error(scenario.source + ": fluid.wall_gap_mm needs fluid.model \"rft\", " +
                             "\"stokeslets\" or \"plates\" (the " +
                             ChoiceText(kFluidModelNames, scenario.fluid.model) +
                             " model is free space only)");
  }
  if (scenario.fluid.model == FluidModel::kRibbon) {
    RibbonSettings ribbon;
    ribbon.modes = scenario.fluid.ribbon.modes;
    fluid.ribbon = ribbon;
  }
  if (scenario.fluid.model == FluidModel::kPlates) {
    PlateSettings plates;
    plates.points_across = scenario.fluid.plates.points_across;
    plates.quadrature_refinement = scenario.fluid.plates.quadrature_refinement;
    plates.richardson = scenario.fluid.plates.richardson;
    plates.wall_distance_m = fluid.wall_distance_m;
    fluid.plates = plates;
  }
  return fluid;
}


int ScenarioLinkCount(const ScenarioConfig& scenario) {
  std::string source;
  const ModelPtr model = LoadScenarioModel(scenario, &source);
  IpmcActuatorsOverrides overrides;
  overrides.plants = scenario.model.plants;
  overrides.dynamics = scenario.model.dynamics;
  std::optional<IpmcActuatorsConfig> actuators;
  try {
    actuators = IpmcActuatorsConfig::FromModel(model.get(), overrides);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(source + ": " + e.what());
  }
  if (!actuators) {
    throw std::runtime_error(source + ": model has no IPMC actuators (custom text ipmc_links)");
  }
  return static_cast<int>(actuators->chains.size());
}

}  // namespace ipmc
