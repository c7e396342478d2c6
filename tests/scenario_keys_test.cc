// The key reference (sim/core/scenario_keys.h) against the scenario reader:
// every key of the table is read back through ParseScenario, so the table
// cannot state a key, a default or a range the reader does not have. And
// the resolved scenario a run records (ResolvedScenarioToml) reads back to
// itself.
#include <gtest/gtest.h>
#include <toml++/toml.h>

#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "sim/core/data_paths.h"
#include "sim/core/key_builder.h"
#include "sim/core/keys_command.h"
#include "sim/core/scenario.h"
#include "sim/core/scenario_keys.h"
#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/io/toml.h"
#include "sim/optimize/optimize_file.h"

namespace ipmc {
namespace {

// A scenario file beside the shipped ones, so that "../models/..." resolves.
std::string Source() { return ScenariosDir() + "/keys_test.toml"; }

std::string ModelLine() { return "model = \"" + ModelsDir() + "/flagellum3.xml\"\n"; }

// A scenario with `key = value` (dotted, at the top level) and what the
// key needs (its table's kind); the model unless the key is model.
std::string ScenarioWith(const KeySpec& key, const std::string& value) {
  std::string text = std::string(key.name) == "model" ? "" : ModelLine();
  if (!key.applies_when.empty()) text += key.applies_when + "\n";
  return text + key.name + " = " + value + "\n";
}

// The scenario without the key (its kind only).
std::string ScenarioWithout(const KeySpec& key) {
  std::string text = ModelLine();
  if (!key.applies_when.empty()) text += key.applies_when + "\n";
  return text;
}

std::string Resolved(const std::string& text) {
  return ResolvedScenarioToml(ParseScenario(text, Source()));
}

TEST(ScenarioKeysTest, EveryKeyTakesItsDefaultAndItsExampleAndRefusesItsRefusedValue) {
  int defaults = 0, refusals = 0;
  for (const KeySpec& key : ScenarioKeys()) {
    SCOPED_TRACE(key.name);
    ASSERT_NE(FindScenarioKey(key.name), nullptr);
    if (!key.default_toml.empty()) {
      // The default is the default: stating it changes nothing.
      EXPECT_EQ(Resolved(ScenarioWith(key, key.default_toml)), Resolved(ScenarioWithout(key)));
      ++defaults;
    }
    if (!key.example_toml.empty()) {
      EXPECT_NO_THROW(ParseScenario(ScenarioWith(key, key.example_toml), Source()));
    }
    EXPECT_TRUE(!key.default_toml.empty() || !key.example_toml.empty())
        << "a key needs an accepted value";
    if (!key.refused_toml.empty()) {
      try {
        ParseScenario(ScenarioWith(key, key.refused_toml), Source());
        ADD_FAILURE() << key.name << " = " << key.refused_toml << " was accepted";
      } catch (const InputError& error) {
        EXPECT_EQ(error.key(), key.name) << error.what();
        EXPECT_EQ(error.where().line,
                  std::string(key.name) == "model" ? 1u : 2u + !key.applies_when.empty())
            << error.what();
        ++refusals;
      }
    }
    if (key.type == KeyType::kChoice) {
      for (const std::string& choice : KeyChoices(key)) {
        EXPECT_NO_THROW(ParseScenario(ScenarioWith(key, "\"" + choice + "\""), Source())) << choice;
      }
    }
  }
  // Every key but those whose default is the model's (model, link_lengths_mm,
  // segments_per_link, plants, dynamics, timestep_s, fluid.viscosity_Pa_s,
  // fluid.rft_coefficients, fluid.model) or the wave's (fluid.rft_wavelength_mm) and
  // fluid.wall_gap_mm (no wall), the Stokeslets' points per mm and blob
  // (from the strip's radius) and the five controller.link_* gains (every
  // link the scalar key's), include (no files), the strip's four keys
  // (stating one generates the flagellum), the plant's eight number keys
  // (the assigned plant) and metrics.from_cycle (the first cycle after the
  // start ramp) and drive.csv (no file) has one; every key but the booleans
  // and the unbounded ones has a refused value.
  EXPECT_EQ(defaults, static_cast<int>(ScenarioKeys().size()) - 33);
  EXPECT_GE(refusals, 20);
}

// A TOML value as text that compares numbers by value ("5e-4" and
// "0.0005", "8" and "8.0" alike).
std::string Canonical(const toml::node& node) {
  if (node.is_number()) return FormatShortest(node.value<double>().value());
  if (const auto* text = node.as_string()) return "\"" + text->get() + "\"";
  if (const auto* boolean = node.as_boolean()) return boolean->get() ? "true" : "false";
  std::string joined;
  if (const auto* array = node.as_array()) {
    for (const toml::node& element : *array) joined += Canonical(element) + ",";
  }
  return "[" + joined + "]";
}

// Each key's reader and writer are one entry of the table: a key's example
// value read into a scenario comes back from ResolvedScenarioToml as it was
// given (the model's and drive.csv's paths come back resolved, output.dir and include,
// which is read before the keys, not at all).
TEST(ScenarioKeysTest, EveryKeysExampleIsWrittenBackAsRead) {
  int compared = 0;
  for (const KeySpec& key : ScenarioKeys()) {
    SCOPED_TRACE(key.name);
    ASSERT_NE(key.read, nullptr);
    const std::string value = !key.example_toml.empty() ? key.example_toml : key.default_toml;
    const bool file = std::string(key.name) == "model" || std::string(key.name) == "drive.csv";
    if (key.write == nullptr || file || value.empty()) continue;
    const toml::table given = ParseToml("value = " + value, "example");
    const toml::table resolved = ParseToml(Resolved(ScenarioWith(key, value)), "resolved");
    const toml::node_view<const toml::node> written = resolved.at_path(key.name);
    ASSERT_TRUE(written) << key.name << " is not in the resolved scenario";
    EXPECT_EQ(Canonical(*written.node()), Canonical(*given.get("value")));
    ++compared;
  }
  EXPECT_EQ(compared, static_cast<int>(ScenarioKeys().size()) - 4);
}

TEST(ScenarioKeysTest, BoundsInTheTableAreTheReadersBounds) {
  // A bounded number just outside its bound is refused, just inside accepted.
  for (const KeySpec& key : ScenarioKeys()) {
    if (key.type != KeyType::kNumber || key.lower == Bound::kNone) continue;
    SCOPED_TRACE(key.name);
    const double inside = key.lower == Bound::kOpen ? key.minimum + 1e-12 : key.minimum;
    std::ostringstream refused, accepted;
    refused.precision(17);
    accepted.precision(17);
    refused << std::showpoint << (key.lower == Bound::kOpen ? key.minimum : key.minimum - 1e-12);
    accepted << std::showpoint << inside;
    EXPECT_THROW(ParseScenario(ScenarioWith(key, refused.str()), Source()), InputError);
    if (std::string(key.name) == "controller.sample_rate_Hz") continue;  // 1e-12 Hz: no whole steps
    EXPECT_NO_THROW(ParseScenario(ScenarioWith(key, accepted.str()), Source()));
  }
}

// One range check (NumberOutOfRange) for scenario files and for an
// optimisation's designs (DesignScenario): a value outside a key's lower
// bound is refused by both, with the same message.
TEST(ScenarioKeysTest, ScenarioFilesAndDesignsShareTheRangeCheck) {
  int compared = 0;
  for (const KeySpec& key : ScenarioKeys()) {
    if (key.type != KeyType::kNumber || key.lower == Bound::kNone || key.read == nullptr) continue;
    SCOPED_TRACE(key.name);
    const double refused = key.lower == Bound::kOpen ? key.minimum : key.minimum - 1.0;
    std::string from_file, from_design;
    try {
      ParseScenario(ScenarioWith(key, FloatText(refused)), Source());
    } catch (const InputError& error) {
      from_file = error.message();
    }
    const ScenarioConfig base = ParseScenario(ScenarioWithout(key), Source());
    DesignKey design;
    design.name = design.key = key.name;
    try {
      DesignScenario(base, {design}, {refused});
    } catch (const InputError& error) {
      from_design = error.message();
    }
    EXPECT_NE(from_file.find(" must be "), std::string::npos) << from_file;
    EXPECT_EQ(from_design, from_file);
    ++compared;
  }
  EXPECT_GE(compared, 20);
}

TEST(ScenarioKeysTest, TheReaderAllowsExactlyTheTablesKeys) {
  EXPECT_EQ(ScenarioKeysUnder("fluid"),
            (std::vector<std::string>{"viscosity_Pa_s", "rft_coefficients", "rft_wavelength_mm",
                                      "wall_gap_mm", "model", "stokeslet_width_points",
                                      "stokeslet_points_per_mm", "stokeslet_blob_mm",
                                      "stokeslet_shape_tolerance_rad",
                                      "stokeslet_secant_reach_rad", "stokeslet_fit_tolerance",
                                      "ribbon_modes", "ribbon_shape_tolerance_rad",
                                      "ribbon_secant_reach_rad", "ribbon_fit_tolerance",
                                      "plate_points_across", "plate_quadrature_refinement",
                                      "plate_richardson", "plate_shape_tolerance_rad",
                                      "plate_secant_reach_rad", "plate_fit_tolerance"}));
  std::vector<std::string> tables = {""};
  for (const std::string& name : ScenarioKeysUnder("")) {
    if (!ScenarioKeysUnder(name).empty()) tables.push_back(name);
  }
  // The top level, strip, plant, controller, waveform, drive, fluid,
  // metrics, electrical, output.
  EXPECT_EQ(tables.size(), 10u);
  for (const std::string& table : tables) {
    SCOPED_TRACE(table);
    const std::string unknown = table.empty() ? "speed" : table + ".speed";
    try {
      ParseScenario(ModelLine() + unknown + " = 1\n", Source());
      ADD_FAILURE() << unknown << " was accepted";
    } catch (const InputError& error) {
      EXPECT_EQ(error.problem(), InputProblem::kUnknownKey) << error.what();
      EXPECT_EQ(error.key(), unknown);
      std::string allowed;
      for (const std::string& name : ScenarioKeysUnder(table)) {
        allowed += (allowed.empty() ? "" : ", ") + name;
      }
      EXPECT_EQ(error.allowed(), allowed);
    }
  }
}

TEST(ScenarioKeysTest, TheResolvedScenarioReadsBackToItself) {
  const std::string pid = Resolved(ModelLine() + "controller.kp = 0.30000000000000004\n");
  // Doubles keep all their digits.
  EXPECT_NE(pid.find("0.30000000000000004"), std::string::npos) << pid;
  const std::string fractional_wave = Resolved(
      ModelLine() + "waveform.kind = \"fractional\"\nwaveform.c_um = 300\nwaveform.alpha = 0.7\n");
  const std::string eq15 = Resolved(
      ModelLine() + "controller.kind = \"fractional\"\ncontroller.realisation = \"eq15\"\n");
  const std::string generated =
      Resolved("link_lengths_mm = [8, 10.5, 12]\nsegments_per_link = 2\nplants = \"table2\"\n"
               "timestep_s = 5e-4\nfluid.viscosity_Pa_s = 2e-3\n");
  for (const char* name : {"paper.toml", "paper_fractional.toml"}) {
    const std::string path = ScenariosDir() + "/" + std::string(name);
    const std::string resolved = ResolvedScenarioToml(LoadScenario(path));
    EXPECT_EQ(Resolved(resolved), resolved) << name;
    EXPECT_EQ(resolved.find("out/paper"), std::string::npos) << "output.dir is no part of a run";
  }
  for (const std::string& resolved : {pid, fractional_wave, eq15, generated}) {
    EXPECT_EQ(Resolved(resolved), resolved);
  }
  EXPECT_NE(eq15.find("eq15"), std::string::npos) << eq15;
  EXPECT_EQ(eq15.find("gain"), std::string::npos) << eq15;
}

TEST(ScenarioKeysTest, PaperScenarioNamesEveryKeyAndWhereTheReferenceIs) {
  std::ifstream file(ScenariosDir() + "/paper.toml");
  std::stringstream text;
  text << file.rdbuf();
  for (const KeySpec& key : ScenarioKeys()) {
    std::string last = key.name;
    last = last.substr(last.rfind('.') + 1);
    EXPECT_TRUE(std::regex_search(text.str(), std::regex("\\b" + last + "\\b"))) << key.name;
  }
  EXPECT_NE(text.str().find("docs/SCENARIO_KEYS.md"), std::string::npos);
}

TEST(ScenarioKeysTest, TheReferenceListsEveryKeyInBothFormats) {
  const std::string text = KeyReference(KeyFormat::kText);
  const std::string markdown = KeyReference(KeyFormat::kMarkdown);
  for (const auto* keys : {&ScenarioKeys(), &SweepFileKeys()}) {
    for (const KeySpec& key : *keys) {
      EXPECT_NE(text.find(std::string("  ") + key.name + " ("), std::string::npos) << key.name;
      EXPECT_NE(markdown.find(std::string("| `") + key.name + "` |"), std::string::npos)
          << key.name;
    }
  }
}

}  // namespace
}  // namespace ipmc
