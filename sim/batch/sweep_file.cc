// Sweep files: read strictly (like scenario files); every point's scenario
// is built at the TOML level (sim/core/scenario_overrides.h) and read by
// ParseScenario before anything runs.
#include "sim/batch/sweep_file.h"

#include "sim/batch/sweep_gait.h"

#include <mujoco/mujoco.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/core/data_paths.h"
#include "sim/core/link_sensors.h"
#include "sim/core/scenario_keys.h"
#include "sim/core/scenario_overrides.h"
#include "sim/core/simulation.h"
#include "sim/io/files.h"
#include "sim/io/toml.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;

using namespace sweep_keys;

std::string TypeName(const toml::node& node) { return TomlTypeName(node.type()); }

// A swept value as the table prints it: strings bare, numbers shortest,
// arrays in JSON syntax (strings quoted), so that SweepTableJson reads
// them back.
std::string ValueText(const toml::node& node, bool in_array = false) {
  if (const auto* text = node.as_string()) {
    return in_array ? nlohmann::json(text->get()).dump() : OneLine(text->get());
  }
  if (const auto* integer = node.as_integer()) return std::to_string(integer->get());
  if (const auto* number = node.as_floating_point()) return FormatShortest(number->get());
  if (const auto* boolean = node.as_boolean()) return boolean->get() ? "true" : "false";
  if (const auto* array = node.as_array()) {
    std::string joined = "[";
    for (const toml::node& element : *array) {
      if (joined.size() > 1) joined += ", ";
      joined += ValueText(element, true);
    }
    return joined + "]";
  }
  std::ostringstream text;  // dates, times, tables: TOML's own text
  node.visit([&](const auto& value) { text << value; });
  return OneLine(text.str());
}

// A swept key of a grid and its values.
struct Axis {
  ScenarioOverride key;  // value: unused
  std::vector<const toml::node*> values;
};

// One point of the sweep file: its overrides and their printed values
// (one per swept key).
struct PointOverrides {
  std::vector<ScenarioOverride> overrides;
  std::vector<std::string> printed;
};

class SweepReader : public ScenarioOverrides {
 public:
  explicit SweepReader(std::string source) : ScenarioOverrides(std::move(source)) {}

  SweepPlan Read(const std::string& toml_text);

 private:
  void ReadBase(const toml::table& root);
  void RejectUnknownKeys(const toml::table& root) const;
  void FlattenGrid(const toml::table& table, const std::string& prefix,
                   std::vector<Axis>* axes) const;
  std::vector<PointOverrides> ReadGrid(const toml::table& grid, std::uint32_t grid_line,
                                       const std::vector<const ScenarioOverride*>& fixed,
                                       std::vector<std::string>* keys) const;
  std::vector<PointOverrides> ReadPoints(const toml::array& tables,
                                         const std::vector<const ScenarioOverride*>& fixed,
                                         std::vector<std::string>* keys) const;
  // Reads the base with `overrides`; stops the sweep on a fatal error.
  OverriddenScenario Check(const std::vector<const ScenarioOverride*>& overrides) const {
    OverriddenScenario point = ReadScenario(overrides);
    if (point.fatal) throw *point.fatal;
    return point;
  }
};

// The keys of the key table (sim/core/scenario_keys.h).
void SweepReader::RejectUnknownKeys(const toml::table& root) const {
  const std::vector<KeySpec>& allowed = SweepFileKeys();
  std::string names;
  for (const KeySpec& spec : allowed) names += (names.empty() ? "" : ", ") + std::string(spec.name);
  const toml::key* unknown = nullptr;
  for (auto&& [key, node] : root) {
    if (std::any_of(allowed.begin(), allowed.end(),
                    [&](const KeySpec& spec) { return key == spec.name; })) {
      continue;
    }
    if (unknown == nullptr || key.source().begin.line < unknown->source().begin.line) {
      unknown = &key;
    }
  }
  if (unknown != nullptr) {
    Fail(unknown->source().begin.line,
         "unknown key '" + std::string(unknown->str()) + "' (allowed: " + names + ")",
         InputProblem::kUnknownKey, std::string(unknown->str()));
  }
}

void SweepReader::ReadBase(const toml::table& root) {
  const auto it = root.find(kBase);
  if (it == root.end()) {
    Fail(0, std::string(kBase) + " is required (the scenario file to sweep)",
         InputProblem::kMissing, kBase);
  }
  const std::uint32_t line = it->first.source().begin.line;
  const toml::value<std::string>* base = it->second.as_string();
  if (base == nullptr) {
    Fail(line, std::string(kBase) + " must be a string (got " + TypeName(it->second) + ")",
         InputProblem::kWrongType, kBase);
  }
  fs::path path(base->get());
  if (path.is_relative()) path = fs::path(source_).parent_path() / path;
  const std::string base_path = path.lexically_normal().string();
  std::error_code ignored;
  if (!fs::is_regular_file(base_path, ignored) || !std::ifstream(base_path).good()) {
    Fail(line, std::string(kBase) + ": cannot open '" + base_path + "'", InputProblem::kUnreadable,
         kBase);
  }
  LoadBase(base_path);
}

void SweepReader::FlattenGrid(const toml::table& table, const std::string& prefix,
                              std::vector<Axis>* axes) const {
  ForEachLeaf(
      table, prefix, [&](const std::string& name, const toml::key& key, const toml::node& node) {
        const std::string grid_key = std::string(kGrid) + "." + name;
        const std::uint32_t line = key.source().begin.line;
        const toml::array* values = node.as_array();
        if (values == nullptr) {
          Fail(line, grid_key + " must be an array of values (got " + TypeName(node) + ")",
               InputProblem::kWrongType, grid_key);
        }
        if (values->empty()) Fail(line, grid_key + " must not be empty");
        Axis axis;
        axis.key = OverrideAt(name, key, nullptr);
        for (const toml::node& value : *values) {
          if (value.is_table()) {
            Fail(line, grid_key +
                           " must hold values, not tables (use [[point]] to change several keys "
                           "together)");
          }
          axis.values.push_back(&value);
        }
        axes->push_back(std::move(axis));
      });
}

// The points of a [grid], in order; their swept keys go to `keys`.
std::vector<PointOverrides> SweepReader::ReadGrid(const toml::table& grid, std::uint32_t grid_line,
                                                  const std::vector<const ScenarioOverride*>& fixed,
                                                  std::vector<std::string>* keys) const {
  std::vector<Axis> axes;
  FlattenGrid(grid, "", &axes);
  if (axes.empty()) Fail(grid_line, std::string(kGrid) + " must sweep at least one key");
  std::sort(axes.begin(), axes.end(),
            [](const Axis& a, const Axis& b) { return OverrideBefore(a.key, b.key); });
  std::vector<const ScenarioOverride*> all_keys = fixed;
  double count = 1.0;
  for (const Axis& axis : axes) {
    all_keys.push_back(&axis.key);
    keys->push_back(axis.key.key);
    count *= static_cast<double>(axis.values.size());
  }
  RejectRepeatedKeys(all_keys);
  if (count > kMaxPoints) {
    Fail(grid_line, "the grid has " + FormatShortest(count) + " points (at most " +
                        FormatShortest(kMaxPoints) + ")");
  }
  for (const Axis& axis : axes) {
    for (const toml::node* value : axis.values) {
      ScenarioOverride entry = axis.key;
      entry.value = value;
      Check({&entry});
    }
  }
  // An odometer over the axes, the last one fastest.
  std::vector<PointOverrides> points;
  std::vector<size_t> digit(axes.size(), 0);
  for (long index = 0; index < static_cast<long>(count); ++index) {
    PointOverrides point;
    for (size_t k = 0; k < axes.size(); ++k) {
      ScenarioOverride entry = axes[k].key;
      entry.value = axes[k].values[digit[k]];
      point.printed.push_back(ValueText(*entry.value));
      point.overrides.push_back(std::move(entry));
    }
    points.push_back(std::move(point));
    for (size_t k = axes.size(); k-- > 0;) {
      if (++digit[k] < axes[k].values.size()) break;
      digit[k] = 0;
    }
  }
  return points;
}

// The [[point]] tables, in order; every key any of them sets goes to
// `keys`, in the order the keys first appear.
std::vector<PointOverrides> SweepReader::ReadPoints(
    const toml::array& tables, const std::vector<const ScenarioOverride*>& fixed,
    std::vector<std::string>* keys) const {
  std::vector<PointOverrides> points;
  std::vector<ScenarioOverride> first_use;
  for (const toml::node& node : tables) {
    PointOverrides point;
    FlattenOverrides(*node.as_table(), "", &point.overrides);
    std::vector<const ScenarioOverride*> all_keys = fixed;
    for (const ScenarioOverride& entry : point.overrides) {
      all_keys.push_back(&entry);
      Check({&entry});
      const auto seen = std::find_if(first_use.begin(), first_use.end(),
                                     [&](const ScenarioOverride& o) { return o.key == entry.key; });
      if (seen == first_use.end()) {
        first_use.push_back(entry);
      } else if (OverrideBefore(entry, *seen)) {
        *seen = entry;
      }
    }
    RejectRepeatedKeys(all_keys);
    points.push_back(std::move(point));
  }
  std::sort(first_use.begin(), first_use.end(), OverrideBefore);
  for (const ScenarioOverride& entry : first_use) keys->push_back(entry.key);
  for (PointOverrides& point : points) {
    point.printed.assign(keys->size(), "");
    for (const ScenarioOverride& entry : point.overrides) {
      const auto column = std::find(keys->begin(), keys->end(), entry.key) - keys->begin();
      point.printed[column] = ValueText(*entry.value);
    }
  }
  return points;
}

SweepPlan SweepReader::Read(const std::string& toml_text) {
  const toml::table root = ParseToml(toml_text, source_);
  RejectUnknownKeys(root);
  if (root.contains(kGaitSweepKey)) return ReadGaitSweep(root, source_);
  ReadBase(root);

  auto line_of = [&](const char* key) { return root.find(key)->first.source().begin.line; };
  auto fail_type = [&](const char* key, const std::string& expected) {
    Fail(line_of(key),
         std::string(key) + " must be " + expected + " (got " + TypeName(*root.get(key)) + ")",
         InputProblem::kWrongType, key);
  };
  std::vector<ScenarioOverride> fixed;
  if (root.contains(kSet)) {
    const toml::table* set = root[kSet].as_table();
    if (set == nullptr) fail_type(kSet, "a table");
    FlattenOverrides(*set, "", &fixed);
  }
  std::vector<const ScenarioOverride*> fixed_keys;
  for (const ScenarioOverride& entry : fixed) {
    fixed_keys.push_back(&entry);
    Check({&entry});
  }

  const bool has_grid = root.contains(kGrid);
  const bool has_points = root.contains(kPoint);
  if (has_grid && has_points) {
    Fail(std::max(line_of(kGrid), line_of(kPoint)),
         "[grid] and [[point]] cannot be combined (use one or the other)");
  }
  if (!has_grid && !has_points) Fail(0, "needs a [grid] table or [[point]] tables");
  SweepPlan plan;
  plan.source = source_;
  plan.base_path = base_path_;
  if (root.contains(kKeepRuns)) {
    const toml::value<bool>* keep = root[kKeepRuns].as_boolean();
    if (keep == nullptr) fail_type(kKeepRuns, "true or false");
    plan.keep_runs = keep->get();
  }
  std::vector<PointOverrides> points;
  if (has_grid) {
    const toml::table* grid = root[kGrid].as_table();
    if (grid == nullptr) fail_type(kGrid, "a table");
    points = ReadGrid(*grid, line_of(kGrid), fixed_keys, &plan.keys);
  } else {
    const toml::array* tables = root[kPoint].as_array();
    if (tables == nullptr || !tables->is_array_of_tables() || tables->empty()) {
      Fail(line_of(kPoint),
           std::string(kPoint) + " must be one or more tables of overrides ([[point]])");
    }
    points = ReadPoints(*tables, fixed_keys, &plan.keys);
  }

  for (size_t index = 0; index < points.size(); ++index) {
    std::vector<const ScenarioOverride*> overrides = fixed_keys;
    for (const ScenarioOverride& entry : points[index].overrides) overrides.push_back(&entry);
    OverriddenScenario read = Check(overrides);
    SweepPoint point;
    point.index = static_cast<int>(index);
    point.values = std::move(points[index].printed);
    point.scenario = std::move(read.scenario);
    point.error = std::move(read.error);
    point.scenario_toml = std::move(read.text);
    plan.points.push_back(std::move(point));
  }
  return plan;
}

// The number of IPMC links of each model the points use (as the run
// counts them); a model that does not load counts none, and its points
// fail when they run.
int CountLinks(const SweepPlan& plan) {
  std::set<std::string> models;
  for (const SweepPoint& point : plan.points) {
    if (point.scenario) models.insert(point.scenario->model.path);
  }
  int links = 0;
  for (const std::string& model : models) {
    try {
      Simulation sim(LoadModelFile(model), model);
      links = std::max(links, LinkSensors(sim.model(), sim.data(), model).Links());
    } catch (const std::exception&) {
    }
  }
  return links;
}

}  // namespace

SweepPlan ParseSweep(const std::string& toml_text, const std::string& source) {
  SweepReader reader(source);
  SweepPlan plan = reader.Read(toml_text);
  plan.links = CountLinks(plan);
  return plan;
}

SweepPlan LoadSweep(const std::string& path) {
  return ParseSweep(ReadTextFile(path, "sweep file"), path);
}

}  // namespace ipmc
