#include "sim/identify/key_files.h"

#include <filesystem>

#include "sim/core/key_builder.h"
#include "sim/core/model_generator.h"
#include "sim/core/scenario.h"
#include "sim/core/strip_keys.h"
#include "sim/io/files.h"
#include "sim/io/toml.h"

namespace ipmc {
namespace {

// The keys as a scenario that includes the file and generates `links`
// 10 mm links: the scenario reader checks them (one value per link).
ScenarioConfig KeyFileScenario(const std::string& path, int links) {
  const std::string file = std::filesystem::absolute(path).lexically_normal().string();
  std::string lengths;
  for (int q = 0; q < links; ++q) lengths += (q > 0 ? ", " : "") + std::string("10.0");
  return ParseScenario("include = " + *TomlString(file) + "\nlink_lengths_mm = [" + lengths +
                           "]\n",
                       "the keys of " + path);
}

}  // namespace

int KeyFileLinks(const std::string& path, int links) {
  const toml::table table = ParseToml(ReadTextFile(path, "key file"), path);
  for (const char* section : {"plant", "controller"}) {
    const toml::table* keys = table[section].as_table();
    if (keys == nullptr) continue;
    for (const auto& [key, value] : *keys) {
      if (std::string(key.str()).rfind("link_", 0) == 0 && value.is_array()) {
        return static_cast<int>(value.as_array()->size());
      }
    }
  }
  return links;
}

bool KeyFileHasLinkArrays(const std::string& path) {
  return KeyFileLinks(path, 0) > 0;
}

std::vector<IpmcLinkParams> PlantsOfKeyFile(const std::string& path, int links) {
  const ScenarioConfig scenario = KeyFileScenario(path, KeyFileLinks(path, links));
  const FlagellumSpec spec = ScenarioFlagellumSpec(scenario.model);
  const IpmcModelKind kind = spec.ipmc_model == "g2" ? IpmcModelKind::kG2 : IpmcModelKind::kG1;
  std::vector<IpmcLinkParams> plants;
  for (int q = 0; q < spec.Links(); ++q) {
    IpmcLinkParams p = AssignedLinkParams(PlantAssignment::kUniform, q + 1, kind,
                                          spec.link_lengths_mm[q] * 1e-3);
    if (!spec.a0_mm_per_V.empty()) p.a0_mm_per_V = spec.a0_mm_per_V[q];
    if (!spec.b1.empty()) p.b1 = spec.b1[q];
    if (!spec.b2_s2.empty()) p.b2_s2 = spec.b2_s2[q];
    if (!spec.alpha.empty()) p.alpha = spec.alpha[q];
    plants.push_back(p);
  }
  return plants;
}

KeyFileControllers ControllersOfKeyFile(const std::string& path, int links) {
  links = KeyFileLinks(path, links);
  const ScenarioConfig scenario = KeyFileScenario(path, links);
  KeyFileControllers controllers;
  for (int q = 0; q < links; ++q) {
    controllers.pid.push_back(scenario.controller.LinkPid(q));
    controllers.fractional.push_back(scenario.controller.LinkFractional(q));
  }
  return controllers;
}

}  // namespace ipmc
