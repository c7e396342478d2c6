// How a coupled model is stepped (the MJCF field and its choices): mj_step
// with the bodies' inertia, or the Stokes-flow step without it
// (plugin/dynamics/stokes_step.h, docs/DYNAMICS.md).
#pragma once

#include <stdexcept>
#include <string>

namespace ipmc {

// MJCF: text ipmc_dynamics, inertial (default) | stokes.
enum class Dynamics { kInertial, kStokes };
constexpr char kAttrDynamics[] = "ipmc_dynamics";

// Throws std::invalid_argument naming the field and its choices.
inline Dynamics ParseDynamics(const std::string& text) {
  if (text == "inertial") return Dynamics::kInertial;
  if (text == "stokes") return Dynamics::kStokes;
  throw std::invalid_argument(std::string(kAttrDynamics) + " must be inertial or stokes (got '" +
                              text + "')");
}

inline const char* DynamicsName(Dynamics dynamics) {
  return dynamics == Dynamics::kStokes ? "stokes" : "inertial";
}

}  // namespace ipmc
