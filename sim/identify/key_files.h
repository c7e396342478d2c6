// Key files: TOML files of scenario keys that a scenario includes, such as
// the plant.toml `identify` writes ([plant]) and the gains.toml `design`
// writes ([controller]), read link by link for the design and analysis
// commands (design, bode and step with --plant-file / --gains-file).
#pragma once

#include <string>
#include <vector>

#include "controllers/fractional_integrator.h"
#include "controllers/pid.h"
#include "sim/linear/ipmc_link_model.h"

namespace ipmc {

// The links a key file speaks of: the length of its per-link arrays
// (plant.link_*, controller.link_*), else `links` (its keys then hold for
// any number of links; 3, the paper's, by default). Throws InputError
// naming the file if it cannot be read or is not TOML.
int KeyFileLinks(const std::string& path, int links = 3);
// Whether the file has per-link arrays (its links are theirs).
bool KeyFileHasLinkArrays(const std::string& path);

// The plants of links 1..KeyFileLinks(path, links) the [plant] keys of
// `path` give (eq. 7 scaled to a 10 mm link where they give none). Throws
// InputError naming the file and key.
std::vector<IpmcLinkParams> PlantsOfKeyFile(const std::string& path, int links = 3);

// Link q's controller as the [controller] keys of `path` set it, for
// links 1..n (n = KeyFileLinks(path, links)): the PID's and the fractional
// integrator's Config, each key over the defaults.
struct KeyFileControllers {
  std::vector<PidController::Config> pid;
  std::vector<FractionalIntegrator::Config> fractional;
};
KeyFileControllers ControllersOfKeyFile(const std::string& path, int links = 3);

}  // namespace ipmc
