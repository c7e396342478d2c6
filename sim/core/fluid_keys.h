// The fluid as scenario keys: [fluid], the viscosity and the RFT
// coefficients over the model's, a wall, the fluid model
// (plugin/fluid/fluid_model.h) and the regularized Stokeslets' points.
#pragma once

#include <vector>

#include "sim/core/scenario_keys.h"

namespace ipmc {

// The [fluid] keys of the key table, in its order.
std::vector<KeySpec> FluidKeys();

}  // namespace ipmc
