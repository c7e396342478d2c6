// What every command of ipmc-swim shares when it registers itself.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "plugin/actuators/ipmc_link_model.h"

namespace ipmc {

// Adds subcommand `name` to `app`; every option added to it shows its
// default in --help (options whose default is a placeholder, such as 0
// for "the kind's own", clear it with ->default_str("")).
inline CLI::App* AddCommand(CLI::App& app, const std::string& name,
                            const std::string& description) {
  CLI::App* command = app.add_subcommand(name, description);
  command->option_defaults()->always_capture_default();
  return command;
}

// --plant: one of the paper's two link models, g1 (eq. 5) or g2 (eq. 6).
inline CLI::Option* AddPlantOption(CLI::App* command, std::string& plant) {
  return command->add_option("--plant", plant, "g1 (eq. 5) | g2 (eq. 6)")
      ->check(CLI::IsMember({"g1", "g2"}));
}
inline IpmcModelKind PlantKind(const std::string& plant) {
  return plant == "g2" ? IpmcModelKind::kG2 : IpmcModelKind::kG1;
}

}  // namespace ipmc
