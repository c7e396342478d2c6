#include "sim/core/fluid_keys.h"

#include <cmath>
#include <string>

#include "ipmc_swim/fields.h"
#include "sim/core/key_builder.h"
#include "sim/core/scenario.h"

namespace ipmc {
namespace {

// fluid.model: its choices and their meaning from the registry.
KeySpec ModelKey() {
  std::string meaning =
      "The fluid model (plugin/fluid/fluid_model.h, docs/FLUIDS.md), over the model's "
      "`ipmc_fluid_model`:";
  std::vector<std::string> choices;
  for (const FluidModelDescription& entry : FluidModelDescriptions()) {
    meaning += std::string(choices.empty() ? " " : "; ") + "\"" + entry.name + "\", " +
               entry.summary;
    choices.push_back(entry.name);
  }
  return Key(kFluidModelKey, KeyType::kChoice, "", QuotedChoices(choices),
             "the model's `ipmc_fluid_model`, else \"rft\"", meaning + ". Its parameters, "
             "fluid.stokeslet_* and so on, apply only with fluid.model set")
      .Example("\"stokeslets\"")
      .Refused("\"bem\"")
      .Choices(FluidModelChoices())
      .Reads([](const KeyValue& v, ScenarioConfig& c) { c.fluid.model = v.Choice(); })
      .Writes([](const ScenarioConfig& c) {
        return c.fluid.model ? TomlString(*c.fluid.model) : kLeftOut;
      });
}

// The fluid and the model that computes its drag: viscosity, RFT coefficients, wall.
std::vector<KeySpec> RftKeys() {
  using T = KeyType;
  return {
      Key("fluid.viscosity_Pa_s", T::kNumber, "Pa s", "> 0",
          "the model's `ipmc_rft_viscosity_Pa_s`",
          "Dynamic viscosity of the fluid, overriding the model's")
          .Example("1e-3")
          .Refused("0")
          .Above(0.0)
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.fluid.viscosity_Pa_s = v.Number(); })
          .Writes([](const ScenarioConfig& c) {
            return c.fluid.viscosity_Pa_s ? TomlFloat(*c.fluid.viscosity_Pa_s) : kLeftOut;
          }),
      Key("fluid.rft_coefficients", T::kChoice, "", "", "the model's `ipmc_rft_coefficients`",
          "RFT drag coefficients (plugin/fluid/rft_drag.h), overriding the model's; "
          "gray_hancock and lighthill follow fluid.rft_wavelength_mm; ribbon is calibrated at "
          "set-up on the converged flat plates of the model's own straight strip, per segment: "
          "its share of the broadside and axial drag per length and its own rotational drag "
          "(plugin/fluid/ribbon_coefficients.h, docs/FLUIDS.md); ribbon_fitted is ribbon with "
          "the broadside drag x 1.14 and the rotational drag x 0.85, fitted to the plates' swim "
          "and fluid power in the paper's default job (for that strip and gait)")
          .Example("\"lighthill\"")
          .Refused("\"direct\"")
          .Choices(kRftCoefficientNames)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.fluid.rft_coefficients = ChoiceValue(kRftCoefficientNames, v.Choice());
          })
          .Writes([](const ScenarioConfig& c) {
            return c.fluid.rft_coefficients
                       ? TomlString(ChoiceText(kRftCoefficientNames, *c.fluid.rft_coefficients))
                       : kLeftOut;
          }),
      Key("fluid.rft_wavelength_mm", T::kNumber, "mm", "finite and > 0", "waveform.wavelength_mm",
          "Wavelength in the Gray-Hancock and Lighthill coefficients, over the model's "
          "`ipmc_rft_wavelength_m`")
          .Example("32.0")
          .Refused("0")
          .Above(0.0)
          .Reads(
              [](const KeyValue& v, ScenarioConfig& c) { c.fluid.rft_wavelength_mm = v.Number(); })
          .Writes([](const ScenarioConfig& c) {
            return c.fluid.rft_wavelength_mm ? TomlFloat(*c.fluid.rft_wavelength_mm) : kLeftOut;
          }),
      Key("fluid.wall_gap_mm", T::kNumber, "mm", "> 0", "no wall",
          "A no-slip plane wall this far below the strip's lower edge (the centreline is the "
          "gap plus half the width above it), parallel to the plane the strip beats in: RFT takes "
          "the near-wall coefficients of Katz, Blake & Paveri-Fontana (1975) in place of "
          "fluid.rft_coefficients, Stokeslets and plates the wall's image system; slender-ribbon "
          "theory is free space only")
          .Example("2.0")
          .Refused("0")
          .Above(0.0)
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.fluid.wall_gap_mm = v.Number(); })
          .Writes([](const ScenarioConfig& c) {
            return c.fluid.wall_gap_mm ? TomlFloat(*c.fluid.wall_gap_mm) : kLeftOut;
          }),
      ModelKey(),
  };
}

// A parameter's value as TOML, in its key's type.
std::string ParameterToml(const FluidParameter& p, double value) {
  switch (p.type) {
    case FluidParameter::Type::kInteger:
      return *TomlInteger(static_cast<int>(value));
    case FluidParameter::Type::kBoolean:
      return *TomlBool(value != 0.0);
    case FluidParameter::Type::kNumber:
      break;
  }
  return *TomlFloat(value);
}

// The key fluid.<key> of one model's parameter: its range, default and
// meaning from the parameter, applying only under fluid.model = the model.
KeySpec ParameterKey(const FluidModelDescription& model, const FluidParameter& p) {
  const KeyType type = p.type == FluidParameter::Type::kInteger   ? KeyType::kInteger
                       : p.type == FluidParameter::Type::kBoolean ? KeyType::kBoolean
                                                                   : KeyType::kNumber;
  const bool derived = std::isnan(p.default_value);
  Key key(std::string("fluid.") + p.key, type, p.unit, FluidParameterRange(p),
          p.default_text ? p.default_text : ParameterToml(p, p.default_value), p.meaning);
  KeySpec spec = key.Example(ParameterToml(p, p.example)).Only(kFluidModelKey, model.name);
  if (!derived) spec.default_toml = ParameterToml(p, p.default_value);
  if (type != KeyType::kBoolean) {
    spec.refused_toml = ParameterToml(p, p.minimum_included ? p.minimum - 1 : p.minimum);
    spec.lower = p.minimum_included ? Bound::kClosed : Bound::kOpen;
    spec.minimum = p.minimum;
    if (std::isfinite(p.maximum)) {
      spec.upper = Bound::kClosed;
      spec.maximum = p.maximum;
    }
  }
  const std::string name = p.key;
  spec.read = [name, type](const KeyValue& v, ScenarioConfig& c) {
    c.fluid.parameters[name] = type == KeyType::kInteger   ? v.Integer()
                               : type == KeyType::kBoolean ? v.Boolean()
                                                           : v.Number();
  };
  spec.write = [name, p](const ScenarioConfig& c) -> std::optional<std::string> {
    const auto given = c.fluid.parameters.find(name);
    if (given == c.fluid.parameters.end() || given->second == p.default_value) return kLeftOut;
    return ParameterToml(p, given->second);
  };
  return spec;
}

}  // namespace

std::vector<KeySpec> FluidKeys() {
  std::vector<KeySpec> keys = RftKeys();
  for (const FluidModelDescription& model : FluidModelDescriptions()) {
    for (const FluidParameter& parameter : model.parameters) {
      keys.push_back(ParameterKey(model, parameter));
    }
  }
  return keys;
}

}  // namespace ipmc
