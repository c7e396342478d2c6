// `resistance` as both front ends run it: a model held rigid at its
// reference pose (qpos0) and the 6 x 6 resistance R of its fluid
// (ipmc_swim/resistance.h: force and torque about the world origin per
// velocity and angular velocity), with Purcell's propulsion matrix for
// one axis; the option table and the JSON file (key "R").
#pragma once

#include <array>
#include <string>

#include "ipmc_swim/resistance.h"
#include "sim/io/option_table.h"

namespace ipmc {

struct ResistanceCommand {
  std::string model;          // an MJCF file
  std::string fluid;          // "": the model's ipmc_fluid_model
  std::string coefficients;   // "": the model's ipmc_rft_coefficients
  double stokeslet_points_per_mm = 0.0;  // 0: the model's (or the default)
  double stokeslet_blob_mm = 0.0;        // 0: the model's (or the default)
  std::string axis = "x";
  std::string out;            // "": no file
};

const OptionTable<ResistanceCommand>& ResistanceOptions();

struct ResistanceOutcome {
  std::array<double, 36> resistance{};  // R, row-major
  PropulsionMatrix propulsion;          // for the command's axis
  std::string json;                     // what `out` holds
};

// Loads the model, computes R and writes `out` (if set) atomically.
// Throws FieldError naming the option for a bad option, and
// std::invalid_argument (the model's field) or std::runtime_error (the
// file) otherwise.
ResistanceOutcome RunResistanceCommand(const ResistanceCommand& command);

// R and A, B, D as the command line prints them.
std::string ResistanceText(const ResistanceCommand& command, const ResistanceOutcome& outcome);

}  // namespace ipmc
