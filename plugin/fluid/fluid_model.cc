#include "plugin/fluid/fluid_model.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "plugin/fluid/plate_fluid.h"
#include "plugin/fluid/ribbon_fluid.h"
#include "plugin/fluid/rft_drag.h"
#include "plugin/fluid/stokeslet_fluid.h"
#include "plugin/mjcf/custom_fields.h"
#include "sim/base/numbers.h"

namespace ipmc {

void Fluid::LocalResistances(const mjModel* /*m*/, const mjData* /*d*/,
                             BodyResistanceBlocks<6>* out) const {
  out->clear();
}

void Fluid::LocalResistances(const mjModel* /*m*/, const mjData* /*d*/,
                             BodyResistanceBlocks<3>* out) const {
  out->clear();
}

const Eigen::MatrixXd* Fluid::InteractionResistance(const mjModel* /*m*/,
                                                    const mjData* /*d*/) const {
  return nullptr;
}

const Eigen::MatrixXd* Fluid::FrameResistance(const mjModel* m, const mjData* d,
                                              Eigen::Matrix<double, 6, 6>* frame,
                                              long* version) const {
  frame->setIdentity();
  *version = -1;
  return InteractionResistance(m, d);
}

bool Fluid::FrameResistanceCubic(const mjModel*, const mjData*, Eigen::Matrix<double, 6, 6>*,
                                 ResistanceCubic*) const {
  return false;
}

const std::vector<int>& Fluid::InteractingBodies() const {
  static const std::vector<int> kNone;
  return kNone;
}

namespace {

constexpr double kUnbounded = std::numeric_limits<double>::infinity();

FluidParameter Parameter(const char* key, const char* field, FluidParameter::Type type,
                         const char* meaning) {
  FluidParameter p{};
  p.key = key;
  p.field = field;
  p.type = type;
  p.unit = "";
  p.field_per_key = 1.0;
  p.meaning = meaning;
  p.minimum_included = true;
  p.maximum = kUnbounded;
  return p;
}

// The range with its bounds times `scale` (the key's unit: 1).
std::string RangeText(const FluidParameter& p, double scale) {
  if (p.type == FluidParameter::Type::kBoolean) return "true or false";
  if (std::isfinite(p.maximum)) {
    return "[" + FormatShortest(p.minimum * scale) + ", " + FormatShortest(p.maximum * scale) +
           "]";
  }
  return (p.minimum_included ? ">= " : "> ") + FormatShortest(p.minimum * scale);
}

}  // namespace

FluidParameter IntegerParameter(const char* key, const char* field, int default_value,
                                int minimum, int maximum, int example, const char* meaning) {
  FluidParameter p = Parameter(key, field, FluidParameter::Type::kInteger, meaning);
  p.default_value = default_value;
  p.example = example;
  p.minimum = minimum;
  p.maximum = maximum;
  return p;
}

FluidParameter NumberParameter(const char* key, const char* field, const char* unit,
                               double field_per_key, double default_value,
                               const char* default_text, double minimum, bool minimum_included,
                               double example, const char* meaning) {
  FluidParameter p = Parameter(key, field, FluidParameter::Type::kNumber, meaning);
  p.unit = unit;
  p.field_per_key = field_per_key;
  p.default_value = default_value;
  p.default_text = default_text;
  p.example = example;
  p.minimum = minimum;
  p.minimum_included = minimum_included;
  return p;
}

FluidParameter BooleanParameter(const char* key, const char* field, bool default_value,
                                const char* meaning) {
  FluidParameter p = Parameter(key, field, FluidParameter::Type::kBoolean, meaning);
  p.default_value = default_value;
  p.example = !default_value;
  p.minimum = 0.0;
  p.maximum = 1.0;
  return p;
}

FluidParameter SetsResolution(FluidParameter parameter) {
  parameter.resolution = true;
  return parameter;
}

std::string FluidParameterRange(const FluidParameter& p) { return RangeText(p, 1.0); }

std::optional<double> FluidParameterValue(const mjModel* m, const RftDragOverrides& overrides,
                                          const char* model, const FluidParameter& p) {
  std::optional<double> value;
  if (const auto given = overrides.fluid_parameters.find(p.field);
      given != overrides.fluid_parameters.end()) {
    value = given->second;
  } else {
    value = FindCustomScalar(m, p.field);
  }
  if (!value) {
    if (std::isnan(p.default_value)) return std::nullopt;
    return p.default_value * p.field_per_key;
  }
  const double in_key_unit = *value / p.field_per_key;
  const bool whole = p.type == FluidParameter::Type::kNumber || std::trunc(*value) == *value;
  const bool above = p.minimum_included ? in_key_unit >= p.minimum : in_key_unit > p.minimum;
  if (!(whole && above && in_key_unit <= p.maximum)) {
    const char* kind = p.type == FluidParameter::Type::kInteger   ? "a whole number in "
                       : p.type == FluidParameter::Type::kBoolean ? "0 or 1: "
                                                                   : "";
    throw std::invalid_argument(std::string(model) + ": " + p.field + " must be " + kind +
                                RangeText(p, p.field_per_key) + " (got " +
                                FormatShortest(*value) + ")");
  }
  return value;
}

const std::vector<FluidModelEntry>& FluidModels() {
  static const std::vector<FluidModelEntry> kModels = {
      {{"rft", "local resistive-force theory", {}, true}, RftDrag::Make, nullptr},
      {{"stokeslets", StokesletFluid::kSummary, StokesletFluid::Parameters(), true},
       StokesletFluid::Make, StokesletFluid::ForcePoints},
      {{"ribbon", RibbonFluid::kSummary, RibbonFluid::Parameters(), false}, RibbonFluid::Make,
       nullptr},
      {{"plates", PlateFluid::kSummary, PlateFluid::Parameters(), true}, PlateFluid::Make,
       PlateFluid::ForcePoints},
  };
  return kModels;
}

const std::vector<FluidModelDescription>& FluidModelDescriptions() {
  static const std::vector<FluidModelDescription> kDescriptions(FluidModels().begin(),
                                                                FluidModels().end());
  return kDescriptions;
}

const FluidModelDescription* FindFluidModelDescription(const std::string& name) {
  for (const FluidModelDescription& description : FluidModelDescriptions()) {
    if (name == description.name) return &description;
  }
  return nullptr;
}

double FluidForcePoints(const mjModel* m) {
  const std::optional<RftDragConfig> config = RftDragConfig::FromModel(m);
  if (!config) return 0.0;
  const FluidModelEntry& model = ChosenFluidModel(m, {});
  if (model.force_points == nullptr) return 0.0;
  return model.force_points(m, RftDrag(m, *config), {});
}

const FluidModelEntry* FindFluidModel(const std::string& name) {
  for (const FluidModelEntry& entry : FluidModels()) {
    if (name == entry.name) return &entry;
  }
  return nullptr;
}

std::string FluidModelChoices() {
  std::string choices;
  for (const FluidModelEntry& entry : FluidModels()) {
    choices += (choices.empty() ? "" : "|") + std::string(entry.name);
  }
  return choices;
}

std::vector<std::string> FluidModelFields() {
  std::vector<std::string> fields = {kAttrFluidModel};
  for (const FluidModelEntry& entry : FluidModels()) {
    for (const FluidParameter& parameter : entry.parameters) fields.push_back(parameter.field);
  }
  return fields;
}

const FluidModelEntry& ChosenFluidModel(const mjModel* m, const RftDragOverrides& overrides) {
  const std::string name =
      overrides.fluid_model.value_or(FindCustomText(m, kAttrFluidModel).value_or("rft"));
  const FluidModelEntry* entry = FindFluidModel(name);
  if (entry == nullptr) {
    throw std::invalid_argument(std::string(kAttrFluidModel) + " = '" + name +
                                "': not a fluid model (" + FluidModelChoices() + ")");
  }
  return *entry;
}

void RequireNoMujocoFluid(const mjModel* m) {
  if (m->opt.viscosity == 0.0 && m->opt.density == 0.0) return;
  bool fluidshape = false;
  for (int g = 0; g < m->ngeom; ++g) fluidshape = fluidshape || m->geom_fluid[mjNFLUID * g] != 0;
  std::ostringstream msg;
  msg << "the model's <option viscosity=\"" << m->opt.viscosity << "\" density=\""
      << m->opt.density << "\">" << (fluidshape ? " (with a geom's fluidshape)" : "")
      << " turns on MuJoCo's own fluid forces, which would add to the ipmc_rft_ fluid's drag: "
         "set both to 0 (the drag's fluid is " << kAttrViscosity << " and "
      << kAttrFluidDensity << ")";
  throw std::invalid_argument(msg.str());
}

std::unique_ptr<Fluid> MakeFluid(const mjModel* m, const RftDrag& segments,
                                 const RftDragOverrides& overrides) {
  RequireNoMujocoFluid(m);
  const FluidModelEntry& entry = ChosenFluidModel(m, overrides);
  if (std::string(entry.name) != "rft" && !segments.head_geom_ids().empty()) {
    const int g = segments.head_geom_ids().front();
    const char* name = mj_id2name(m, mjOBJ_GEOM, g);
    throw std::invalid_argument(std::string("fluid model ") + entry.name + ": geom '" +
                                (name ? std::string(name) : std::to_string(g)) + "' is a " +
                                (m->geom_type[g] == mjGEOM_SPHERE ? "sphere" : "ellipsoid") +
                                ", which only the rft model represents (its exact Stokes drag); "
                                "use fluid model rft, or leave it out of " + kAttrGeoms);
  }
  if (WallDistance_m(segments) && !entry.wall) {
    throw std::invalid_argument(std::string("fluid model ") + entry.name +
                                ": free space only, but the model has a wall (" +
                                kAttrWallDistance + ", near-wall coefficients)");
  }
  return entry.make(m, segments, overrides);
}

std::optional<double> WallDistance_m(const RftDrag& segments) {
  if (segments.config().model != CoefficientModel::kNearWall) return std::nullopt;
  return segments.config().wall_distance_m;
}

}  // namespace ipmc
