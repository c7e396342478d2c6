#include "sim/core/strip_keys.h"

#include <cstddef>
#include <string>
#include <utility>

#include "sim/base/error.h"
#include "sim/core/key_builder.h"
#include "sim/core/model_generator.h"
#include "sim/core/scenario.h"

namespace ipmc {
namespace {

constexpr char kPlantModel[] = "plant.model";

// A number of the strip: > 0, unset the generator's (Table 1's) value.
template <std::optional<double> StripConfig::*kField>
Key StripKey(const char* name, const char* unit, const char* default_text, const char* meaning,
             const char* example_toml, const char* field) {
  Key key(name, KeyType::kNumber, unit, "> 0", default_text, meaning);
  key.Example(example_toml)
      .Refused("0")
      .Above(0.0)
      .Fields(field)
      .Reads([](const KeyValue& v, ScenarioConfig& c) { c.model.strip.*kField = v.Number(); })
      .Writes([](const ScenarioConfig& c) {
        const std::optional<double>& value = c.model.strip.*kField;
        return value ? TomlFloat(*value) : kLeftOut;
      });
  return key;
}

// A plant parameter for every link; unset, the assigned plant's.
template <std::optional<double> PlantConfig::*kField>
Key PlantKey(const char* name, const char* unit, const char* allowed, const char* meaning,
             const char* example_toml, const char* field) {
  Key key(name, KeyType::kNumber, unit, allowed,
          "the link's assigned plant (eq. 7 scaled to its length: `plants`)", meaning);
  key.Example(example_toml)
      .Fields(field)
      .Reads([](const KeyValue& v, ScenarioConfig& c) { c.model.plant.*kField = v.Number(); })
      .Writes([](const ScenarioConfig& c) {
        const std::optional<double>& value = c.model.plant.*kField;
        return value ? TomlFloat(*value) : kLeftOut;
      });
  return key;
}

// The same parameter per link, over the scalar key.
template <std::vector<double> PlantConfig::*kField>
Key LinkPlantKey(const char* name, const char* unit, const char* allowed, const char* meaning,
                 const char* example_toml, const char* field) {
  Key key =
      PerLinkKey<ModelScenario, PlantConfig, &ScenarioConfig::model, &ModelScenario::plant, kField>(
          name, unit, allowed, meaning, example_toml);
  key.Fields(field);
  return key;
}

// One value per link of `links`: the array if set, else the scalar for
// every link, else none (the assigned plant).
std::vector<double> PerLink(const std::optional<double>& scalar, const std::vector<double>& array,
                            int links) {
  if (!array.empty()) return array;
  return scalar ? std::vector<double>(links, *scalar) : std::vector<double>{};
}

}  // namespace

std::vector<KeySpec> StripAndPlantKeys() {
  using T = KeyType;
  std::vector<KeySpec> keys = {
      StripKey<&StripConfig::width_mm>(
          "strip.width_mm", "mm", "3 (Table 1)",
          "Strip width, normal to the beat plane: the links' mass, E I, the drag's equivalent "
          "radius (w + h) / 4 and the Stokeslets' sheet; generates the flagellum",
          "5.0", "width_mm"),
      StripKey<&StripConfig::thickness_um>(
          "strip.thickness_um", "um", "250 (Table 1)",
          "Strip thickness, in the beat plane: E I = E w h^3 / 12 (the hinges' stiffness), the "
          "mass and the equivalent radius; generates the flagellum",
          "200.0", "thickness_um"),
      StripKey<&StripConfig::youngs_modulus_Pa>(
          "strip.youngs_modulus_Pa", "Pa", "0.25e9",
          "Young's modulus E of the strip in bending: the hinges' stiffness E I / s "
          "(docs/MODEL.md); generates the flagellum",
          "0.5e9", "bending_modulus_Pa"),
      StripKey<&StripConfig::density_kg_m3>(
          "strip.density_kg_m3", "kg/m^3", "2000",
          "Strip density: the links' mass (inertial dynamics only); generates the flagellum",
          "1500.0", "density_kg_m3"),
      Key(kPlantModel, T::kChoice, "", "", "\"g1\"",
          "Every link's plant P = s^-0.5 G: g1, G1 = a0 / (b2 s^2 + b1 s + 1) (eq. 5); g2, "
          "G2 = a0 / (b1 s^alpha + 1) (eq. 6); g2 generates the flagellum")
          .Default("\"g1\"")
          .Example("\"g2\"")
          .Refused("\"g3\"")
          .Choices(kPlantModelNames)
          .Fields("ipmc_model")
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.model.plant.model = ChoiceValue(kPlantModelNames, v.Choice());
          })
          .Writes([](const ScenarioConfig& c) {
            return c.model.plant.model == IpmcModelKind::kG1
                       ? kLeftOut
                       : TomlString(ChoiceText(kPlantModelNames, c.model.plant.model));
          }),
      PlantKey<&PlantConfig::a0_mm_per_V>(
          "plant.a0_mm_per_V", "mm/V", "> 0",
          "Static gain a0 of every link's G (free tip deflection per volt); generates the "
          "flagellum",
          "0.5", "a0_mm_per_V")
          .Refused("0")
          .Above(0.0),
      LinkPlantKey<&PlantConfig::link_a0_mm_per_V>("plant.link_a0_mm_per_V", "mm/V", "each > 0",
                                                   "One a0 per link, in order, over a0",
                                                   "[0.5, 0.4, 0.3]", "a0_mm_per_V")
          .Refused("[0.5, 0]")
          .Above(0.0),
      PlantKey<&PlantConfig::b1>("plant.b1", "s (g1) or s^alpha (g2)", "> 0",
                                 "b1 of every link's G; generates the flagellum", "0.03", "b1")
          .Refused("0")
          .Above(0.0),
      LinkPlantKey<&PlantConfig::link_b1>("plant.link_b1", "s (g1) or s^alpha (g2)", "each > 0",
                                          "One b1 per link, in order, over b1",
                                          "[0.03, 0.03, 0.02]", "b1")
          .Refused("[0.03, -1]")
          .Above(0.0),
      PlantKey<&PlantConfig::b2_s2>("plant.b2_s2", "s^2", ">= 0",
                                    "b2 of every link's G1 (its corner 1 / sqrt(b2) rad/s); "
                                    "generates the flagellum",
                                    "0.002", "b2_s2")
          .Refused("-1")
          .AtLeast(0.0)
          .Only(kPlantModel, "g1"),
      LinkPlantKey<&PlantConfig::link_b2_s2>("plant.link_b2_s2", "s^2", "each >= 0",
                                             "One b2 per link, in order, over b2_s2",
                                             "[0.002, 0.002, 0.003]", "b2_s2")
          .Refused("[0.002, -1]")
          .AtLeast(0.0)
          .Only(kPlantModel, "g1"),
      PlantKey<&PlantConfig::alpha>("plant.alpha", "", "(0, 2)",
                                    "Order alpha of every link's G2; generates the flagellum",
                                    "1.8", "alpha")
          .Refused("2")
          .Above(0.0)
          .Below(2.0)
          .Only(kPlantModel, "g2"),
      LinkPlantKey<&PlantConfig::link_alpha>("plant.link_alpha", "", "each in (0, 2)",
                                             "One alpha per link, in order, over alpha",
                                             "[1.8, 1.7, 1.6]", "alpha")
          .Refused("[1.8, 2]")
          .Above(0.0)
          .Below(2.0)
          .Only(kPlantModel, "g2"),
  };
  return keys;
}

FlagellumSpec ScenarioFlagellumSpec(const ModelScenario& model) {
  FlagellumSpec spec;
  if (!model.link_lengths_mm.empty()) spec.link_lengths_mm = model.link_lengths_mm;
  if (model.segments_per_link > 0) spec.segments_per_link = model.segments_per_link;
  const StripConfig& strip = model.strip;
  if (strip.width_mm) spec.width_mm = *strip.width_mm;
  if (strip.thickness_um) spec.thickness_um = *strip.thickness_um;
  if (strip.youngs_modulus_Pa) spec.bending_modulus_Pa = *strip.youngs_modulus_Pa;
  if (strip.density_kg_m3) spec.density_kg_m3 = *strip.density_kg_m3;
  const PlantConfig& plant = model.plant;
  const int links = spec.Links();
  spec.ipmc_model = ChoiceText(kPlantModelNames, plant.model);
  spec.a0_mm_per_V = PerLink(plant.a0_mm_per_V, plant.link_a0_mm_per_V, links);
  spec.b1 = PerLink(plant.b1, plant.link_b1, links);
  spec.b2_s2 = PerLink(plant.b2_s2, plant.link_b2_s2, links);
  spec.alpha = PerLink(plant.alpha, plant.link_alpha, links);
  return spec;
}

}  // namespace ipmc
