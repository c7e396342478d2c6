#include "plugin/fluid/fluid_model.h"

#include "plugin/fluid/plate_fluid.h"
#include "plugin/fluid/ribbon_fluid.h"
#include "plugin/fluid/rft_drag.h"
#include "plugin/fluid/stokeslet_fluid.h"

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

const std::vector<int>& Fluid::InteractingBodies() const {
  static const std::vector<int> kNone;
  return kNone;
}

const std::vector<FluidModelEntry>& FluidModels() {
  static const std::vector<FluidModelEntry> kModels = {
      {"stokeslets", StokesletFluid::Chosen, StokesletFluid::Make},
      {"ribbon", RibbonFluid::Chosen, RibbonFluid::Make},
      {"plates", PlateFluid::Chosen, PlateFluid::Make},
      {"rft", RftDrag::Chosen, RftDrag::Make},
  };
  return kModels;
}

std::unique_ptr<Fluid> MakeFluid(const mjModel* m, const RftDrag& segments,
                                 const RftDragOverrides& overrides) {
  for (const FluidModelEntry& entry : FluidModels()) {
    if (entry.chosen(segments, overrides)) return entry.make(m, segments, overrides);
  }
  return nullptr;
}

}  // namespace ipmc
