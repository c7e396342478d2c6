#include "sim/core/scenario_simulation.h"

#include <algorithm>
#include <filesystem>
#include <cmath>
#include <memory>
#include <optional>
#include <stdexcept>

#include "ipmc_swim/ipmc_swim.h"
#include "ipmc_swim/fields.h"
#include "sim/base/numbers.h"
#include "sim/core/model_generator.h"
#include "sim/core/sha256.h"
#include "sim/core/step_count.h"
#include "sim/io/files.h"
#include "sim/io/mjcf_edit.h"

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

// The keys (or model file fields) that set the chosen model's force
// points, with their values: the resolution parameters the scenario gives
// ("in.toml: fluid.plate_points_across 16"), else those the model file
// gives ("model.xml: ipmc_fluid_plate_points_across 16"), else the key or
// field that chose the model.
std::string ResolutionSource(const ScenarioConfig& scenario, const mjModel* m,
                             const std::string& model_source, const FluidModelDescription& model) {
  std::string keys, fields;
  for (const FluidParameter& parameter : model.parameters) {
    if (!parameter.resolution) continue;
    if (const auto given = scenario.fluid.parameters.find(parameter.key);
        given != scenario.fluid.parameters.end()) {
      keys += (keys.empty() ? "fluid." : ", fluid.") + std::string(parameter.key) + " " +
              FormatShortest(given->second);
    } else if (const std::optional<double> value = FindCustomScalar(m, parameter.field)) {
      fields += (fields.empty() ? "" : ", ") + std::string(parameter.field) + " " +
                FormatShortest(*value);
    }
  }
  if (!keys.empty()) return scenario.source + ": " + keys;
  if (!fields.empty()) return model_source + ": " + fields;
  return scenario.fluid.model ? scenario.source + ": " + kFluidModelKey
                              : model_source + ": " + kAttrFluidModel;
}

// Throws naming what sets the chosen model's force points
// (ResolutionSource) if they are more than the machine holds or factors in
// reasonable time (CheckStokesletSize), before any step. Bad settings are
// left to the simulation, which names the model.
void CheckFluidResolution(const ScenarioConfig& scenario, const mjModel* m,
                          const std::string& model_source) {
  double points = 0.0;
  const FluidModelDescription* model = nullptr;
  try {
    points = FluidForcePoints(m);
    if (points == 0.0) return;
    model = FindFluidModelDescription(FindCustomText(m, kAttrFluidModel).value_or("rft"));
  } catch (const std::exception&) {
    return;
  }
  if (model == nullptr) return;
  CheckStokesletSize(points, scenario.run.allow_long,
                     ResolutionSource(scenario, m, model_source, *model));
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

namespace {

// The scenario's fluid settings written into the model's fields (m: the
// model before them, xml its text).
std::string WithFluidFields(std::string xml, const ScenarioConfig& scenario, const mjModel* m) {
  const ScenarioFluidFields fluid = ScenarioFluidOverrides(scenario, m);
  if (fluid.coefficients) {
    xml = SetMjcfCustomField(xml, "text", kAttrCoefficients, CoefficientModelName(*fluid.coefficients));
    if (*fluid.coefficients != CoefficientModel::kDirect) {
      // Only a direct coefficient set may keep its coefficients.
      xml = RemoveMjcfCustomField(xml, kAttrXiNormal);
      xml = RemoveMjcfCustomField(xml, kAttrXiTangential);
    }
  }
  if (fluid.wavelength_m) {
    xml = SetMjcfCustomField(xml, "numeric", kAttrWavelength, FormatShortest(*fluid.wavelength_m));
  }
  if (fluid.wall_distance_m) {
    xml = SetMjcfCustomField(xml, "numeric", kAttrWallDistance,
                             FormatShortest(*fluid.wall_distance_m));
    xml = SetMjcfCustomField(xml, "text", kAttrCoefficients,
                             CoefficientModelName(CoefficientModel::kNearWall));
  }
  if (fluid.fluid_model) xml = SetMjcfCustomField(xml, "text", kAttrFluidModel, *fluid.fluid_model);
  for (const auto& [field, value] : fluid.parameters) {
    xml = SetMjcfCustomField(xml, "numeric", field, FormatShortest(value));
  }
  return xml;
}

}  // namespace

// The hinge_damping_scale a run wrote into its model.xml (a field of the
// program's, which the library does not read).
constexpr char kAppliedDampingScaleField[] = "scenario_hinge_damping_scale";

std::string ScenarioModelXml(const ScenarioConfig& scenario, std::string* source) {
  *source = scenario.model.path;
  ModelPtr model;
  std::string xml;
  if (!scenario.model.Generated()) {
    model = LoadModelFile(scenario.model.path);  // names what is wrong with the file
    xml = ReadTextFile(scenario.model.path, "model file");
  } else {
    *source = scenario.source + " (generated flagellum)";
    xml = GeneratedScenarioMjcf(scenario);
    model = LoadModelString(xml);
  }
  const mjModel* m = model.get();
  if (scenario.run.timestep_s) {
    xml = SetMjcfOption(xml, "timestep", FormatShortest(*scenario.run.timestep_s));
  }
  const bool drag = FindCustomScalar(m, kAttrViscosity).has_value();
  if (scenario.fluid.viscosity_Pa_s) {
    if (!drag) {
      throw std::runtime_error(NoDragMessage(*source, scenario.source, "fluid.viscosity_Pa_s"));
    }
    xml = SetMjcfCustomField(xml, "numeric", kAttrViscosity,
                             FormatShortest(*scenario.fluid.viscosity_Pa_s));
  }
  // A run's model.xml holds its joints' damping already scaled, and says by
  // how much: the scale is taken against the model as first written, so the
  // same scenario over a run's model.xml is the same run.
  const double scaled = FindCustomScalar(m, kAppliedDampingScaleField).value_or(1.0);
  if (scenario.model.hinge_damping_scale != scaled) {
    xml = ScaleMjcfJointDamping(xml, scenario.model.hinge_damping_scale / scaled);
    xml = SetMjcfCustomField(xml, "numeric", kAppliedDampingScaleField,
                             FormatShortest(scenario.model.hinge_damping_scale));
  }
  if (scenario.model.plants) {
    xml = SetMjcfCustomField(xml, "text", kAttrPlants, PlantAssignmentName(*scenario.model.plants));
  }
  if (scenario.model.dynamics) {
    xml = SetMjcfCustomField(xml, "text", kAttrDynamics, DynamicsName(*scenario.model.dynamics));
  }
  // Without drag the fluid keys are refused (LoadScenarioSimulation).
  if (drag) xml = WithFluidFields(std::move(xml), scenario, m);
  return xml;
}

ModelPtr LoadScenarioModel(const ScenarioConfig& scenario, std::string* source) {
  const std::string xml = ScenarioModelXml(scenario, source);
  const std::string directory =
      scenario.model.Generated() ? "" : std::filesystem::path(scenario.model.path).parent_path().string();
  try {
    return LoadModelString(xml, directory);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(*source + " with " + scenario.source + "'s settings: " + e.what());
  }
}

std::unique_ptr<Simulation> LoadScenarioSimulation(const ScenarioConfig& scenario) {
  std::string source;
  ModelPtr model = LoadScenarioModel(scenario, &source);
  // Before the simulation's first evaluation factors a dense mobility.
  CheckFluidResolution(scenario, model.get(), source);
  auto sim = std::make_unique<Simulation>(std::move(model), source);
  if (!(IsAttached(sim->data()) && FluidOf(sim->data()).drag)) {
    // Only the keys the scenario sets.
    std::string keys;
    const auto name = [&keys](bool set, const char* key) {
      if (set) keys += (keys.empty() ? "" : ", ") + std::string(key);
    };
    name(scenario.fluid.rft_coefficients.has_value(), "fluid.rft_coefficients");
    name(scenario.fluid.rft_wavelength_mm.has_value(), "fluid.rft_wavelength_mm");
    name(scenario.fluid.wall_gap_mm.has_value(), "fluid.wall_gap_mm");
    name(scenario.fluid.model && *scenario.fluid.model != "rft", kFluidModelKey);
    if (!keys.empty()) {
      throw std::runtime_error(NoDragMessage(sim->source(), scenario.source, keys));
    }
  }
  return sim;
}

ScenarioFluidFields ScenarioFluidOverrides(const ScenarioConfig& scenario, const mjModel* m) {
  constexpr double kMmToM = 1e-3;
  ScenarioFluidFields fluid;
  if (scenario.fluid.rft_coefficients && scenario.fluid.wall_gap_mm) {
    throw std::runtime_error(scenario.source +
                             ": fluid.rft_coefficients and fluid.wall_gap_mm exclude each other "
                             "(near a wall RFT takes the near-wall coefficients)");
  }
  fluid.coefficients = scenario.fluid.rft_coefficients;
  fluid.wavelength_m =
      scenario.fluid.rft_wavelength_mm.value_or(scenario.waveform.wavelength_mm) * kMmToM;
  if (scenario.fluid.wall_gap_mm) {
    fluid.wall_distance_m = *scenario.fluid.wall_gap_mm * kMmToM + 0.5 * StripWidth_m(m);
  }
  fluid.fluid_model = scenario.fluid.model;
  const FluidModelDescription* model = FindFluidModelDescription(
      fluid.fluid_model.value_or(FindCustomText(m, kAttrFluidModel).value_or("rft")));
  if (model == nullptr) return fluid;  // the error the simulation reports, naming the field
  if (scenario.fluid.wall_gap_mm && !model->wall) {
    std::vector<std::string> walled;
    for (const FluidModelDescription& entry : FluidModelDescriptions()) {
      if (entry.wall) walled.push_back(entry.name);
    }
    throw std::runtime_error(scenario.source + ": fluid.wall_gap_mm needs fluid.model " +
                             QuotedChoices(walled) + " (the " + model->name +
                             " model is free space only)");
  }
  for (const FluidParameter& parameter : model->parameters) {
    const auto given = scenario.fluid.parameters.find(parameter.key);
    if (given == scenario.fluid.parameters.end()) continue;
    fluid.parameters[parameter.field] = given->second * parameter.field_per_key;
  }
  return fluid;
}


int ScenarioLinkCount(const ScenarioConfig& scenario) {
  std::string source;
  const ModelPtr model = LoadScenarioModel(scenario, &source);
  int links = 0;
  try {
    links = ModelLinkCount(model.get());
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(source + ": " + e.what());
  }
  if (links == 0) {
    throw std::runtime_error(source + ": model has no IPMC actuators (custom text ipmc_links)");
  }
  return links;
}

namespace {
OustaloupConfig OustaloupOf(const OustaloupBand& band) {
  OustaloupConfig config;
  config.order = band.order;
  config.w_low_rad_s = band.low_rad_s;
  config.w_high_rad_s = band.high_rad_s;
  config.n = band.pairs;
  config.variant = band.two_n_plus_one ? OustaloupVariant::k2NPlus1 : OustaloupVariant::kNPairs;
  return config;
}
}  // namespace

std::vector<IpmcLinkParams> AttachedLinkPlants(const mjData* d) {
  std::vector<IpmcLinkParams> plants;
  for (int q = 0; IsAttached(d) && q < LinkCount(d); ++q) {
    const LinkPlantParameters plant = LinkPlantOf(d, q);
    IpmcLinkParams params;
    params.kind = plant.g2 ? IpmcModelKind::kG2 : IpmcModelKind::kG1;
    params.a0_mm_per_V = plant.a0_mm_per_V;
    params.b1 = plant.b1;
    params.b2_s2 = plant.b2_s2;
    params.alpha = plant.alpha;
    params.integrator = OustaloupOf(plant.integrator);
    params.fractional_lag = OustaloupOf(plant.fractional_lag);
    plants.push_back(params);
  }
  return plants;
}

std::vector<IpmcLinkParams> ScenarioLinkPlants(const ScenarioConfig& scenario) {
  const std::unique_ptr<Simulation> sim = LoadScenarioSimulation(scenario);
  std::vector<IpmcLinkParams> plants = AttachedLinkPlants(sim->data());
  if (plants.empty()) {
    throw std::runtime_error(scenario.source + ": the links' plants need IPMC actuators");
  }
  return plants;
}

}  // namespace ipmc
