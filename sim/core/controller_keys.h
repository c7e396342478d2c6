// The controller as scenario keys: [controller], the kind and what every
// kind shares (sample rate, voltage limit, clamp), the PID's gains (eq. 12)
// and the fractional integrator's (eq. 13-15), each one value for every
// link or one per link.
#pragma once

#include <vector>

#include "sim/core/scenario_keys.h"

namespace ipmc {

// The [controller] keys of the key table, in its order.
std::vector<KeySpec> ControllerKeys();

}  // namespace ipmc
