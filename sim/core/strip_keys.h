// The strip and its plants as scenario keys: [strip] (width, thickness,
// Young's modulus, density) and [plant] (eq. 5 / eq. 6 per link). Any of
// them generates the flagellum (sim/core/model_generator.h) from the
// generator's defaults with these values over them, as link_lengths_mm
// does: the drag's equivalent radius follows the width and thickness
// ((w + h) / 4), the hinges' stiffness E I / s and the links' mass follow
// the strip, and each link gets the plant the keys give it (its own
// plant, not scaled to its length). Unset, the generator's defaults hold
// (Table 1's strip; `ipmc-swim keys` lists them) and each link gets the
// plant its `plants` assignment gives.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "ipmc_swim/fields.h"
#include "sim/linear/ipmc_link_model.h"
#include "sim/core/choice_table.h"
#include "sim/core/scenario_keys.h"

namespace ipmc {

struct FlagellumSpec;  // sim/core/model_generator.h

struct StripConfig {
  std::optional<double> width_mm, thickness_um;  // across the beat plane; in it
  std::optional<double> youngs_modulus_Pa;       // E of the hinges' E I
  std::optional<double> density_kg_m3;
  bool Any() const { return width_mm || thickness_um || youngs_modulus_Pa || density_kg_m3; }
};

// plant.model's texts.
inline constexpr ChoiceName<IpmcModelKind> kPlantModelNames[] = {
    {"g1", IpmcModelKind::kG1},
    {"g2", IpmcModelKind::kG2},
};

struct PlantConfig {
  IpmcModelKind model = IpmcModelKind::kG1;  // eq. 5 or eq. 6
  // Every link's value (unset: the assigned plant's) and the per-link
  // arrays over it (empty: every link the scalar's).
  std::optional<double> a0_mm_per_V, b1, b2_s2, alpha;
  std::vector<double> link_a0_mm_per_V, link_b1, link_b2_s2, link_alpha;
  bool Any() const {
    return model != IpmcModelKind::kG1 || a0_mm_per_V || b1 || b2_s2 || alpha || !link_a0_mm_per_V.empty() ||
           !link_b1.empty() || !link_b2_s2.empty() || !link_alpha.empty();
  }
};

// The model a scenario runs: its file, or the flagellum generated in its
// place (link_lengths_mm, segments_per_link or any [strip] or [plant] key),
// and what overrides the model's own fields. Single keys are checked by
// the key table; the generated flagellum as a whole (one value per link
// in every per-link array, ...) by ScenarioFlagellumSpec(...).Validate().
struct ModelScenario {
  std::string path;                     // resolved against the scenario's directory
  std::vector<double> link_lengths_mm;  // non-empty: generate the model instead
  int segments_per_link = 0;            // > 0: generate the model instead
  std::optional<PlantAssignment> plants;  // over the model's ipmc_plants
  StripConfig strip;  // [strip]: any key generates the model
  PlantConfig plant;  // [plant]: likewise
  std::optional<Dynamics> dynamics;  // over the model's ipmc_dynamics
  double hinge_damping_scale = 1.0;  // times every joint's damping

  bool Generated() const {
    return !link_lengths_mm.empty() || segments_per_link > 0 || strip.Any() || plant.Any();
  }
};

// The [strip] and [plant] keys of the key table, in its order.
std::vector<KeySpec> StripAndPlantKeys();

// The flagellum a scenario whose model is Generated() generates: the
// generator's defaults, the scenario's link lengths, sub-segments, strip
// and plants. Throws FieldError naming the FlagellumSpec field (the keys'
// `fields`) when a per-link array does not hold one value per link.
FlagellumSpec ScenarioFlagellumSpec(const ModelScenario& model);

}  // namespace ipmc
