// Controllers retuned for each design (docs/OPTIMIZE.md, "Retuned
// controllers"): every link's controller designed for that link's own
// plant, which the design's link lengths scale (ScaleLinkToLength in
// sim/linear/ipmc_link_model.h: a0 as L^2, b2 as L^4), by
// the project's design tools (sim/identify/controller_design.h) at their
// defaults:
//   pid         eq. 11's J against the reference model 1/((s/5)^1.16 + 1)
//               over 2 s at 10 kHz, minimised by Nelder-Mead from one
//               start: the base's gains over the link's plant gain relative
//               to eq. 7's (a0 / a0_eq7), which is the optimum for a plant
//               that differs only in gain;
//   fractional  eq. 13's K and lambda for the crossover 5 rad/s and the
//               phase margin 75 deg on the link's exact response.
// The result goes into the scenario's controller.link_* gains.
#pragma once

#include "sim/core/scenario.h"

namespace ipmc {

// Crossover and phase margin of the fractional design [rad/s], [deg].
constexpr double kRetuneCrossover_rad_s = 5.0;
constexpr double kRetunePhaseMargin_deg = 75.0;

// The scenario with controller.link_* set to each link's retuned gains.
// Throws std::runtime_error (one line) if a link's design fails.
ScenarioConfig RetunedControllers(const ScenarioConfig& scenario);

}  // namespace ipmc
