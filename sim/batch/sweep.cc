// Sweeps: the sweep file is read strictly (like scenario files), every
// point's scenario is built at the TOML level and read by ParseScenario
// before anything runs, then the points run on a pool of threads, each
// writing only its own row.
#include "sim/batch/sweep.h"

#include <mujoco/mujoco.h>
#include <toml++/toml.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "sim/core/fan_out.h"
#include "sim/core/data_paths.h"
#include "sim/core/link_sensors.h"
#include "sim/core/scenario_keys.h"
#include "sim/core/simulation.h"
#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "plugin/base/error.h"
#include "sim/io/files.h"
#include "plugin/base/numbers.h"
#include "sim/io/toml.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/runs/output.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;

// Sweep file keys.
constexpr char kBase[] = "base";
constexpr char kSet[] = "set";
constexpr char kGrid[] = "grid";
constexpr char kPoint[] = "point";


// A grid this large is a mistake in the sweep file, not a plan.
constexpr double kMaxPoints = 1e6;

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

// One replaced (or added) key of the base scenario.
struct Override {
  std::string key;                // dotted: "waveform.frequency_Hz"
  std::vector<std::string> path;  // {"waveform", "frequency_Hz"}
  const toml::node* value = nullptr;
  std::uint32_t line = 0, column = 0;  // in the sweep file
};

bool Before(const Override& a, const Override& b) {
  return std::make_pair(a.line, a.column) < std::make_pair(b.line, b.column);
}

// A swept key of a grid and its values.
struct Axis {
  Override key;  // value: unused
  std::vector<const toml::node*> values;
};

// The outcome of reading one point's scenario.
struct PointScenario {
  std::optional<ScenarioConfig> scenario;
  std::string error;  // relocated: names the sweep file or the base
  std::optional<InputError> failure;  // the same error with its parts
  // An unknown or ill-typed override, which stops the sweep.
  std::optional<InputError> fatal;
  std::string text;  // the TOML read
};

// One point of the sweep file: its overrides and their printed values
// (one per swept key).
struct PointOverrides {
  std::vector<Override> overrides;
  std::vector<std::string> printed;
};

// Where a scenario reader's error belongs.
struct ErrorOrigin {
  InputLocation where;    // the sweep file's line or the base's
  bool in_sweep = false;  // the key is an override
  bool in_base = false;   // the key is the base's own
};

class SweepReader {
 public:
  explicit SweepReader(std::string source) : source_(std::move(source)) {}

  // An error in the sweep file itself, at `line` (0: none), about `key`.
  [[noreturn]] void Fail(std::uint32_t line, const std::string& message,
                         InputProblem problem = InputProblem::kBadValue,
                         const std::string& key = "") const {
    throw InputError(problem, {source_, line}, key, message);
  }

  SweepPlan Read(const std::string& toml_text);
  // One scenario: the base (none if base_path is empty) with `overrides`.
  ScenarioConfig ReadOne(const std::string& base_path, const toml::table& overrides);

 private:
  void ReadBase(const toml::table& root);
  void RejectUnknownKeys(const toml::table& root) const;
  std::vector<std::string> SplitKey(const std::string& key, std::uint32_t line) const;
  // The override of dotted key `name`, declared by `key`.
  Override OverrideAt(const std::string& name, const toml::key& key,
                      const toml::node* value) const;
  void FlattenOverrides(const toml::table& table, const std::string& prefix,
                        std::vector<Override>* overrides) const;
  void FlattenGrid(const toml::table& table, const std::string& prefix,
                   std::vector<Axis>* axes) const;
  void RejectRepeatedKeys(std::vector<const Override*> overrides) const;
  std::vector<PointOverrides> ReadGrid(const toml::table& grid, std::uint32_t grid_line,
                                       const std::vector<const Override*>& fixed,
                                       std::vector<std::string>* keys) const;
  std::vector<PointOverrides> ReadPoints(const toml::array& tables,
                                         const std::vector<const Override*>& fixed,
                                         std::vector<std::string>* keys) const;
  toml::table WithOverrides(const std::vector<const Override*>& overrides) const;
  PointScenario ReadScenario(const std::vector<const Override*>& overrides) const;
  ErrorOrigin Locate(const InputError& error,
                    const std::vector<const Override*>& overrides) const;
  // Reads the base with `overrides`; stops the sweep on a fatal error.
  PointScenario Check(const std::vector<const Override*>& overrides) const {
    PointScenario point = ReadScenario(overrides);
    if (point.fatal) throw *point.fatal;
    return point;
  }

  std::string source_;
  std::string base_path_;
  toml::table base_;
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
  base_path_ = path.lexically_normal().string();
  std::error_code ignored;
  if (!fs::is_regular_file(base_path_, ignored) || !std::ifstream(base_path_).good()) {
    Fail(line, std::string(kBase) + ": cannot open '" + base_path_ + "'", InputProblem::kUnreadable,
         kBase);
  }
  const std::string text = ReadTextFile(base_path_, "scenario file");
  base_ = ParseToml(text, base_path_);
  ParseScenario(text, base_path_);  // the base must be a scenario by itself
}

std::vector<std::string> SweepReader::SplitKey(const std::string& key,
                                               std::uint32_t line) const {
  std::vector<std::string> path;
  std::string::size_type start = 0;
  for (;;) {
    const std::string::size_type dot = key.find('.', start);
    path.push_back(key.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
    if (path.back().empty()) Fail(line, "'" + key + "' is not a dotted scenario key");
    if (dot == std::string::npos) return path;
    start = dot + 1;
  }
}

// Calls leaf(dotted name, key, value) for every value under `table` that
// is not a table, a nested table standing for the dotted keys under it.
template <typename Leaf>
void ForEachLeaf(const toml::table& table, const std::string& prefix, const Leaf& leaf) {
  for (auto&& [key, node] : table) {
    const std::string name = prefix + std::string(key.str());
    if (const toml::table* nested = node.as_table()) {
      ForEachLeaf(*nested, name + ".", leaf);
    } else {
      leaf(name, key, node);
    }
  }
}

Override SweepReader::OverrideAt(const std::string& name, const toml::key& key,
                                 const toml::node* value) const {
  Override entry;
  entry.key = name;
  entry.line = key.source().begin.line;
  entry.column = key.source().begin.column;
  entry.path = SplitKey(name, entry.line);
  entry.value = value;
  return entry;
}

void SweepReader::FlattenOverrides(const toml::table& table, const std::string& prefix,
                                   std::vector<Override>* overrides) const {
  ForEachLeaf(table, prefix, [&](const std::string& name, const toml::key& key,
                                 const toml::node& node) {
    overrides->push_back(OverrideAt(name, key, &node));
  });
}

void SweepReader::FlattenGrid(const toml::table& table, const std::string& prefix,
                              std::vector<Axis>* axes) const {
  ForEachLeaf(table, prefix, [&](const std::string& name, const toml::key& key,
                                 const toml::node& node) {
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

// A key given twice, or a key inside another given key (which would
// replace it), is an error.
void SweepReader::RejectRepeatedKeys(std::vector<const Override*> overrides) const {
  std::sort(overrides.begin(), overrides.end(),
            [](const Override* a, const Override* b) { return Before(*a, *b); });
  for (size_t i = 0; i < overrides.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      const Override& earlier = *overrides[j];
      const Override& later = *overrides[i];
      if (later.key == earlier.key) {
        Fail(later.line, later.key + " is given twice (also on line " +
                             std::to_string(earlier.line) + ")");
      }
      for (const auto& [outer, inner] : {std::pair(&earlier, &later), std::pair(&later, &earlier)}) {
        if (inner->key.rfind(outer->key + ".", 0) == 0) {
          Fail(later.line, inner->key + " and " + outer->key + " (lines " +
                               std::to_string(earlier.line) + " and " +
                               std::to_string(later.line) + ") cannot both be given");
        }
      }
    }
  }
}

// The base with `overrides` inserted.
toml::table SweepReader::WithOverrides(const std::vector<const Override*>& overrides) const {
  toml::table root = base_;
  for (const Override* entry : overrides) {
    toml::table* table = &root;
    std::string parent;
    for (size_t i = 0; i + 1 < entry->path.size(); ++i) {
      parent += (i > 0 ? "." : "") + entry->path[i];
      auto it = table->find(entry->path[i]);
      if (it == table->end()) {
        it = table->insert(entry->path[i], toml::table{}).first;
      } else if (!it->second.is_table()) {
        Fail(entry->line, entry->key + ": " + parent + " is not a table in " + base_path_ +
                              " (it is a " + TypeName(it->second) + ")");
      }
      table = it->second.as_table();
    }
    table->insert_or_assign(entry->path.back(), *entry->value);
  }
  return root;
}

// The table holding a dotted key, if the key is there, and its last part.
template <typename Table>
Table* ParentOf(Table* root, const std::string& dotted, std::string* last) {
  Table* table = root;
  std::string::size_type start = 0;
  for (;;) {
    const std::string::size_type dot = dotted.find('.', start);
    const std::string part = dotted.substr(start, dot == std::string::npos ? dot : dot - start);
    auto it = table->find(part);
    if (it == table->end()) return nullptr;
    if (dot == std::string::npos) {
      *last = part;
      return table;
    }
    table = it->second.as_table();
    if (table == nullptr) return nullptr;
    start = dot + 1;
  }
}

// The key at a dotted path of `root`, or nullptr.
const toml::key* FindKey(const toml::table& root, const std::string& dotted) {
  std::string last;
  const toml::table* parent = ParentOf(&root, dotted, &last);
  return parent == nullptr ? nullptr : &parent->find(last)->first;
}

// Removes the key at a dotted path of `root`; false if there is none.
bool EraseKey(toml::table* root, const std::string& dotted) {
  std::string last;
  toml::table* parent = ParentOf(root, dotted, &last);
  return parent != nullptr && parent->erase(last) > 0;
}

// The scenario reader's errors name lines of the serialised base with the
// overrides, which nobody has seen. Moves one to where its key came from:
// the override's line in the sweep file (the key itself, or the first
// override under a table the error is about), else the key's line in the
// base; without a key, "BASE: ...". An error of another file, or a TOML
// syntax error (which cannot come from the serialised text), stays where
// it is.
ErrorOrigin SweepReader::Locate(const InputError& error,
                                const std::vector<const Override*>& overrides) const {
  ErrorOrigin origin;
  origin.where = error.where();
  if (error.where().file != base_path_ || error.where().column > 0) return origin;
  origin.where = {base_path_};
  if (error.where().line == 0 || error.key().empty()) return origin;

  const Override* from = nullptr;
  for (const Override* entry : overrides) {
    if (entry->key == error.key()) from = entry;
  }
  for (const Override* entry : overrides) {
    if (from == nullptr && entry->key.rfind(error.key() + ".", 0) == 0) from = entry;
  }
  if (from != nullptr) {
    origin.in_sweep = true;
    origin.where = {source_, from->line};
  } else if (const toml::key* key = FindKey(base_, error.key())) {
    origin.in_base = true;
    origin.where = {base_path_, key->source().begin.line};
  }
  return origin;
}

PointScenario SweepReader::ReadScenario(const std::vector<const Override*>& overrides) const {
  toml::table root = WithOverrides(overrides);
  PointScenario point;
  for (;;) {
    std::ostringstream text;
    text << root;
    point.text = text.str();
    try {
      point.scenario = ParseScenario(text.str(), base_path_);
      return point;
    } catch (const InputError& failure) {
      const ErrorOrigin origin = Locate(failure, overrides);
      // A base key of the other kind of its table (the override changed
      // the kind): dropped, and read again.
      if (origin.in_base && failure.problem() == InputProblem::kOtherKind &&
          EraseKey(&root, failure.key())) {
        continue;
      }
      const InputError located(failure.problem(), origin.where, failure.key(), failure.message(),
                               failure.allowed());
      point.error = located.what();
      point.failure = located;
      const bool key_or_type = failure.problem() == InputProblem::kUnknownKey ||
                               failure.problem() == InputProblem::kWrongType;
      if (origin.in_sweep && key_or_type) point.fatal = located;
      return point;
    }
  }
}

// The points of a [grid], in order; their swept keys go to `keys`.
std::vector<PointOverrides> SweepReader::ReadGrid(const toml::table& grid,
                                                  std::uint32_t grid_line,
                                                  const std::vector<const Override*>& fixed,
                                                  std::vector<std::string>* keys) const {
  std::vector<Axis> axes;
  FlattenGrid(grid, "", &axes);
  if (axes.empty()) Fail(grid_line, std::string(kGrid) + " must sweep at least one key");
  std::sort(axes.begin(), axes.end(),
            [](const Axis& a, const Axis& b) { return Before(a.key, b.key); });
  std::vector<const Override*> all_keys = fixed;
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
      Override entry = axis.key;
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
      Override entry = axes[k].key;
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
std::vector<PointOverrides> SweepReader::ReadPoints(const toml::array& tables,
                                                    const std::vector<const Override*>& fixed,
                                                    std::vector<std::string>* keys) const {
  std::vector<PointOverrides> points;
  std::vector<Override> first_use;
  for (const toml::node& node : tables) {
    PointOverrides point;
    FlattenOverrides(*node.as_table(), "", &point.overrides);
    std::vector<const Override*> all_keys = fixed;
    for (const Override& entry : point.overrides) {
      all_keys.push_back(&entry);
      Check({&entry});
      const auto seen = std::find_if(first_use.begin(), first_use.end(),
                                     [&](const Override& o) { return o.key == entry.key; });
      if (seen == first_use.end()) {
        first_use.push_back(entry);
      } else if (Before(entry, *seen)) {
        *seen = entry;
      }
    }
    RejectRepeatedKeys(all_keys);
    points.push_back(std::move(point));
  }
  std::sort(first_use.begin(), first_use.end(), Before);
  for (const Override& entry : first_use) keys->push_back(entry.key);
  for (PointOverrides& point : points) {
    point.printed.assign(keys->size(), "");
    for (const Override& entry : point.overrides) {
      const auto column = std::find(keys->begin(), keys->end(), entry.key) - keys->begin();
      point.printed[column] = ValueText(*entry.value);
    }
  }
  return points;
}

SweepPlan SweepReader::Read(const std::string& toml_text) {
  const toml::table root = ParseToml(toml_text, source_);
  RejectUnknownKeys(root);
  ReadBase(root);

  auto line_of = [&](const char* key) { return root.find(key)->first.source().begin.line; };
  auto fail_type = [&](const char* key, const std::string& expected) {
    Fail(line_of(key), std::string(key) + " must be " + expected + " (got " +
                           TypeName(*root.get(key)) + ")",
         InputProblem::kWrongType, key);
  };
  std::vector<Override> fixed;
  if (root.contains(kSet)) {
    const toml::table* set = root[kSet].as_table();
    if (set == nullptr) fail_type(kSet, "a table");
    FlattenOverrides(*set, "", &fixed);
  }
  std::vector<const Override*> fixed_keys;
  for (const Override& entry : fixed) {
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
    std::vector<const Override*> overrides = fixed_keys;
    for (const Override& entry : points[index].overrides) overrides.push_back(&entry);
    PointScenario read = Check(overrides);
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

ScenarioConfig SweepReader::ReadOne(const std::string& base_path, const toml::table& overrides) {
  base_path_ = base_path.empty() ? source_ : base_path;
  if (!base_path.empty()) {
    const std::string text = ReadTextFile(base_path_, "scenario file");
    base_ = ParseToml(text, base_path_);
    ParseScenario(text, base_path_);  // the base must be a scenario by itself
  }
  std::vector<Override> entries;
  FlattenOverrides(overrides, "", &entries);
  std::vector<const Override*> pointers;
  for (const Override& entry : entries) pointers.push_back(&entry);
  RejectRepeatedKeys(pointers);
  PointScenario point = ReadScenario(pointers);
  if (!point.scenario) throw *point.failure;
  return std::move(*point.scenario);
}

// The number of IPMC links of each model the points use (as the run
// counts them); a model that does not load counts none, and its points
// fail when they run.
int CountLinks(const SweepPlan& plan) {
  std::set<std::string> models;
  for (const SweepPoint& point : plan.points) {
    if (point.scenario) models.insert(point.scenario->model_path);
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

// Physics steps of a point's run, for scheduling (0 for a point that will
// not run; the model's own step, unknown here, counts as kDefaultStep_s).
double EstimatedSteps(const SweepPoint& point) {
  constexpr double kDefaultStep_s = 1e-4;
  if (!point.scenario) return 0.0;
  const ScenarioConfig& scenario = *point.scenario;
  return scenario.cycles / std::abs(scenario.waveform.frequency_Hz) /
         scenario.timestep_s.value_or(kDefaultStep_s);
}

// One point's row; `error` receives the failure, if any.
std::vector<std::string> RunPoint(const SweepPlan& plan, const SweepPoint& point,
                                  std::string* error) {
  std::vector<std::string> row = {std::to_string(point.index)};
  row.insert(row.end(), point.values.begin(), point.values.end());
  std::optional<ClosedLoopResult> result;
  *error = point.error;
  if (point.scenario) {
    try {
      result = RunScenario(*point.scenario);
    } catch (const std::exception& failure) {
      *error = OneLine(failure.what());
    }
  }
  row.push_back(result ? columns::kStatusOk : columns::kStatusError);
  row.push_back(result ? "" : *error);
  for (int q = 0; q < plan.links; ++q) {
    if (result && q < static_cast<int>(result->links.size())) {
      const LinkTracking& link = result->links[q];
      for (double value : {link.iae_mm_s, link.itae_mm_s2, link.rms_voltage_V,
                           link.saturated_fraction}) {
        row.push_back(FormatShortest(value));
      }
    } else {
      row.insert(row.end(), std::size(columns::kLinkResults), "");
    }
  }
  if (result) {
    const SwimMetrics& swim = result->swim;
    const double last_cycle = swim.per_cycle.empty() ? 0.0 : swim.per_cycle.back().com_along;
    for (double value : {last_cycle, swim.mean_speed_along_mm_s, swim.reynolds_tip,
                         swim.reynolds_swim}) {
      row.push_back(FormatShortest(value));
    }
  } else {
    row.insert(row.end(), std::size(columns::kSwimResults), "");
  }
  return row;
}

// The status column of a table, checked.
size_t StatusColumn(const std::vector<std::string>& names, const std::string& source) {
  const auto status = std::find(names.begin(), names.end(), columns::kStatus);
  if (names.empty() || names.front() != columns::kPoint || status == names.end() ||
      status + 1 == names.end() || *(status + 1) != columns::kError) {
    throw InputError(InputProblem::kSyntax, {source, 1}, "",
                     "not a sweep table (expected columns point, ..., status, error, ...)");
  }
  return static_cast<size_t>(status - names.begin());
}

// A point index: a whole number >= 0 without a sign.
std::optional<long> PointIndex(const std::string& text) {
  if (text.empty() || text[0] == '-' || text[0] == '+') return std::nullopt;
  return ParseInteger(text);
}

nlohmann::ordered_json NumberJson(const std::string& text) {
  const std::optional<double> value = ParseDouble(text);
  if (!value || !std::isfinite(*value)) return nullptr;
  return *value;
}

nlohmann::ordered_json SweptValueJson(const std::string& text) {
  if (text.empty()) return nullptr;
  if (text == "true") return true;
  if (text == "false") return false;
  // The table writes numbers without a '+' (ValueText): one with it was a string.
  if (text[0] == '+') return text;
  if (const std::optional<long> integer = ParseInteger(text)) return *integer;
  const std::optional<double> value = ParseDouble(text);
  if (value && std::isfinite(*value)) return *value;
  if (text.front() == '[') {
    nlohmann::ordered_json array = nlohmann::ordered_json::parse(text, nullptr, false);
    if (!array.is_discarded()) return array;
  }
  return text;
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

ScenarioConfig ScenarioWithOverrides(const std::string& base_path, const toml::table& overrides,
                                     const std::string& source) {
  return SweepReader(source).ReadOne(base_path, overrides);
}

SweepShard ParseSweepShard(const std::string& text) {
  const std::string::size_type slash = text.find('/');
  std::optional<long> index, count;
  if (slash != std::string::npos) {
    index = ParseInteger(std::string_view(text).substr(0, slash));
    count = ParseInteger(std::string_view(text).substr(slash + 1));
  }
  if (!index || !count || *count < 1 || *index < 1 || *index > *count || *count > INT_MAX) {
    throw std::invalid_argument("sweep: --shard must be i/n with 1 <= i <= n (got '" + text + "')");
  }
  SweepShard shard;
  shard.index = static_cast<int>(*index);
  shard.count = static_cast<int>(*count);
  return shard;
}

std::vector<std::string> SweepColumns(const SweepPlan& plan) {
  std::vector<std::string> names = {columns::kPoint};
  names.insert(names.end(), plan.keys.begin(), plan.keys.end());
  names.push_back(columns::kStatus);
  names.push_back(columns::kError);
  for (int q = 1; q <= plan.links; ++q) {
    for (const char* result : columns::kLinkResults) {
      names.push_back(columns::LinkResult(q, result));
    }
  }
  names.insert(names.end(), std::begin(columns::kSwimResults), std::end(columns::kSwimResults));
  return names;
}

SweepTable RunSweep(const SweepPlan& plan, const SweepOptions& options) {
  if (options.jobs < 1) {
    throw std::invalid_argument("sweep: --jobs must be >= 1 (got " + std::to_string(options.jobs) +
                                ")");
  }
  const SweepShard& shard = options.shard;
  if (shard.count < 1 || shard.index < 1 || shard.index > shard.count) {
    throw std::invalid_argument("sweep: --shard must be i/n with 1 <= i <= n (got " +
                                std::to_string(shard.index) + "/" + std::to_string(shard.count) +
                                ")");
  }
  std::vector<const SweepPoint*> todo;
  for (const SweepPoint& point : plan.points) {
    if (point.index % shard.count == shard.index - 1) todo.push_back(&point);
  }
  SweepTable table;
  table.columns = SweepColumns(plan);
  table.rows.resize(todo.size());
  // Rows go in index order; runs start longest first, so that the last
  // runs to finish are short ones. Finished points keep their rows.
  std::vector<size_t> schedule;
  for (size_t k = 0; k < todo.size(); ++k) {
    if (options.finished != nullptr && options.finished->count(todo[k]->index) > 0) {
      table.rows[k] = options.finished->at(todo[k]->index);
    } else {
      schedule.push_back(k);
    }
  }
  std::stable_sort(schedule.begin(), schedule.end(), [&](size_t a, size_t b) {
    return EstimatedSteps(*todo[a]) > EstimatedSteps(*todo[b]);
  });

  std::mutex progress_mutex;
  int done = 0;
  std::exception_ptr callback_failure;
  std::atomic<bool> stopped{false};  // by a failed callback: no point starts after it
  const auto start = std::chrono::steady_clock::now();
  // A failing progress report (the journal's record) stops the sweep: no
  // point starts after it, and it is rethrown when the running ones are done.
  FanOut(schedule.size(), options.jobs, [&](size_t slot) {
    if (stopped || (options.stop_requested && options.stop_requested())) return;
    const size_t k = schedule[slot];
    std::string error;
    table.rows[k] = RunPoint(plan, *todo[k], &error);
    std::lock_guard<std::mutex> lock(progress_mutex);
    ++done;
    if (!options.on_point_done || callback_failure) return;
    SweepProgress progress;
    progress.done = done;
    progress.total = static_cast<int>(schedule.size());
    progress.point = todo[k]->index;
    progress.ok = table.rows[k][plan.keys.size() + 1] == columns::kStatusOk;
    progress.error = error;
    progress.elapsed_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    progress.row = &table.rows[k];
    try {
      options.on_point_done(progress);
    } catch (...) {
      callback_failure = std::current_exception();
      stopped = true;
    }
  });
  if (callback_failure) std::rethrow_exception(callback_failure);
  table.program_version = ProgramVersion();
  std::map<std::string, std::string> model_sha256;  // by model path; "" for generated
  for (size_t k = 0; k < todo.size(); ++k) {
    const SweepPoint& point = *todo[k];
    if (table.rows[k].empty() || !point.scenario) continue;
    const ScenarioConfig& scenario = *point.scenario;
    const std::string model = scenario.GeneratesModel() ? "" : scenario.model_path;
    if (scenario.GeneratesModel() || model_sha256.count(model) == 0) {
      model_sha256[model] = ScenarioModelSha256(scenario);
    }
    table.provenance[point.index] = {ResolvedScenarioToml(scenario), model_sha256[model]};
  }
  // A stopped sweep: the points that did not run have no row.
  table.rows.erase(std::remove_if(table.rows.begin(), table.rows.end(),
                                  [](const std::vector<std::string>& row) { return row.empty(); }),
                   table.rows.end());
  return table;
}

std::string SweepTableCsv(const SweepTable& table) {
  CsvWriter csv;
  csv.Row(table.columns);
  for (const std::vector<std::string>& row : table.rows) csv.Row(row);
  return csv.Text();
}

nlohmann::ordered_json SweepTableJson(const SweepTable& table) {
  const size_t status = StatusColumn(table.columns, "sweep table");
  nlohmann::ordered_json points = nlohmann::ordered_json::array();
  for (const std::vector<std::string>& row : table.rows) {
    nlohmann::ordered_json point = nlohmann::ordered_json::object();
    for (size_t c = 0; c < table.columns.size() && c < row.size(); ++c) {
      nlohmann::ordered_json& cell = point[table.columns[c]];
      if (const std::optional<long> index = PointIndex(row[c]); c == 0 && index) {
        cell = *index;
      } else if (c == status || c == status + 1) {
        cell = row[c];
      } else if (c < status) {
        cell = SweptValueJson(row[c]);
      } else {
        cell = NumberJson(row[c]);
      }
    }
    points.push_back(std::move(point));
  }
  nlohmann::ordered_json json = {{"columns", table.columns}, {"points", std::move(points)}};
  if (!table.program_version.empty()) json["program_version"] = table.program_version;
  if (!table.provenance.empty()) {
    nlohmann::ordered_json provenance = nlohmann::ordered_json::array();
    for (const auto& [index, point] : table.provenance) {
      provenance.push_back({{"point", index},
                            {"resolved_scenario", point.resolved_scenario},
                            {"model_sha256", point.model_sha256}});
    }
    json["provenance"] = std::move(provenance);
  }
  return json;
}

SweepTable ParseSweepTableCsv(const std::string& csv_text, const std::string& source) {
  const CsvTable csv = CsvTable::Parse(csv_text, source);
  const size_t status = StatusColumn(csv.columns(), source);
  SweepTable table;
  table.columns = csv.columns();
  std::set<long> indices;
  for (size_t r = 0; r < csv.Rows(); ++r) {
    const std::vector<std::string>& row = csv.Row(r);
    const InputLocation where{source, static_cast<std::uint32_t>(csv.Line(r))};
    const std::optional<long> index = PointIndex(row[0]);
    if (!index) {
      throw InputError(InputProblem::kBadValue, where, columns::kPoint,
                       "point must be a whole number >= 0 (got '" + row[0] + "')",
                       "a whole number >= 0");
    }
    if (!indices.insert(*index).second) {
      throw InputError(InputProblem::kBadValue, where, columns::kPoint,
                       "point " + row[0] + " appears twice");
    }
    // The results after status and error: numbers in a point that ran.
    if (row[status] == columns::kStatusOk) {
      for (size_t c = status + 2; c < row.size(); ++c) {
        const std::optional<double> value = ParseDouble(row[c]);
        if (!value || !std::isfinite(*value)) {
          throw InputError(InputProblem::kBadValue, where, table.columns[c],
                           table.columns[c] + " must be a finite number (got '" + row[c] + "')",
                           "a finite number");
        }
      }
    }
    table.rows.push_back(row);
  }
  return table;
}

// The program version and provenance of the table's JSON (SweepTableJson).
void ReadSweepTableProvenance(const std::string& json_path, SweepTable* table) {
  const nlohmann::ordered_json json =
      nlohmann::ordered_json::parse(ReadTextFile(json_path, "sweep table"), nullptr, false);
  const auto fail = [&](const std::string& key) {
    throw InputError(InputProblem::kSyntax, {json_path}, key,
                     "not a sweep table's JSON (" + key + " missing or malformed)");
  };
  if (!json.is_object()) fail("columns");
  if (json.contains("program_version")) {
    if (!json["program_version"].is_string()) fail("program_version");
    table->program_version = json["program_version"].get<std::string>();
  }
  if (!json.contains("provenance")) return;
  if (!json["provenance"].is_array()) fail("provenance");
  for (const nlohmann::ordered_json& point : json["provenance"]) {
    if (!point.is_object() || !point.contains("point") || !point["point"].is_number_integer() ||
        !point.contains("resolved_scenario") || !point["resolved_scenario"].is_string() ||
        !point.contains("model_sha256") || !point["model_sha256"].is_string()) {
      fail("provenance");
    }
    table->provenance[point["point"].get<int>()] = {point["resolved_scenario"].get<std::string>(),
                                                    point["model_sha256"].get<std::string>()};
  }
}

SweepTable LoadSweepTableCsv(const std::string& path) {
  SweepTable table = ParseSweepTableCsv(ReadTextFile(path, "sweep table"), path);
  const fs::path json = fs::path(path).replace_extension(".json");
  std::error_code ignored;
  if (fs::path(path).extension() == ".csv" && fs::is_regular_file(json, ignored)) {
    ReadSweepTableProvenance(json.string(), &table);
  }
  return table;
}

SweepTable MergeSweepTables(const std::vector<SweepTable>& tables,
                            const std::vector<std::string>& sources, bool allow_missing) {
  if (tables.empty() || tables.size() != sources.size()) {
    throw std::invalid_argument("merge: needs one or more tables, each with its file name");
  }
  SweepTable merged;
  merged.columns = tables.front().columns;
  std::map<long, std::pair<const std::vector<std::string>*, size_t>> rows;  // -> row, table
  for (size_t t = 0; t < tables.size(); ++t) {
    const SweepTable& table = tables[t];
    StatusColumn(table.columns, sources[t]);
    if (table.columns != merged.columns) {
      size_t c = 0;
      while (c < table.columns.size() && c < merged.columns.size() &&
             table.columns[c] == merged.columns[c]) {
        ++c;
      }
      const std::string theirs = c < table.columns.size() ? "'" + table.columns[c] + "'" : "none";
      const std::string ours = c < merged.columns.size() ? "'" + merged.columns[c] + "'" : "none";
      throw InputError(InputProblem::kSyntax, {sources[t]}, "",
                       "columns differ from " + sources.front() + "'s (column " +
                           std::to_string(c + 1) + ": " + theirs + " vs " + ours + ")");
    }
    if (!table.program_version.empty()) {
      if (!merged.program_version.empty() && merged.program_version != table.program_version) {
        throw InputError(InputProblem::kBadValue, {sources[t]}, "program_version",
                         "made by ipmc-swim " + table.program_version + ", the tables before by " +
                             merged.program_version + " (merge tables of one program)");
      }
      merged.program_version = table.program_version;
    }
    for (const std::vector<std::string>& row : table.rows) {
      const std::optional<long> index = row.empty() ? std::nullopt : PointIndex(row[0]);
      if (!index) {
        throw InputError(InputProblem::kMissing, {sources[t]}, columns::kPoint,
                         "a row without a point index");
      }
      const auto [it, added] = rows.emplace(*index, std::make_pair(&row, t));
      const int point = static_cast<int>(*index);
      if (added && table.provenance.count(point) > 0) {
        merged.provenance[point] = table.provenance.at(point);
      }
      if (!added) {
        throw InputError(InputProblem::kBadValue, {sources[t]}, columns::kPoint,
                         "point " + row[0] + " is also in " + sources[it->second.second]);
      }
    }
  }
  long expected = 0;
  for (const auto& [index, row] : rows) {
    if (index != expected && !allow_missing) {
      std::string files;
      for (const std::string& source : sources) files += (files.empty() ? "" : ", ") + source;
      throw std::runtime_error("merge: point " + std::to_string(expected) +
                               " is missing (in none of " + files + "; they hold points up to " +
                               std::to_string(rows.rbegin()->first) + ")");
    }
    merged.rows.push_back(*row.first);
    ++expected;
  }
  return merged;
}

void WriteSweepTable(const std::string& prefix, const SweepTable& table) {
  EnsureParentDirectory(prefix);
  const std::string json = SweepTableJson(table).dump(2) + "\n";
  WriteFilesTogether({{prefix + ".csv", SweepTableCsv(table)}, {prefix + ".json", json}});
}

}  // namespace ipmc
