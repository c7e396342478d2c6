// Optimisation files: read strictly, every field checked here before any run.
#include "sim/optimize/optimize_file.h"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <iterator>
#include <set>
#include <utility>

#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/core/scenario_keys.h"
#include "sim/core/scenario_overrides.h"
#include "sim/core/scenario_simulation.h"
#include "sim/core/simulation.h"
#include "sim/io/columns.h"
#include "sim/io/files.h"
#include "sim/io/toml.h"
#include "sim/runs/run_warnings.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;

constexpr char kBase[] = "base";
constexpr char kSet[] = "set";
constexpr char kVariable[] = "variable";
constexpr char kSum[] = "sum";
constexpr char kObjective[] = "objective";
constexpr char kConstraint[] = "constraint";
constexpr char kAlgorithm[] = "algorithm";
constexpr char kControllers[] = "controllers";
constexpr int kMaxEvaluations = 100000;
constexpr int kMaxStarts = 64;

// The values of a design key as the key table's reader takes them.
class DesignValue : public KeyValue {
 public:
  DesignValue(const KeySpec& spec, std::vector<double> values, bool array)
      : spec_(spec), name_(spec.name), values_(std::move(values)), array_(array) {}
  const std::string& name() const override { return name_; }
  const std::string& source() const override { return name_; }
  double Number() const override { return Bounded(values_.at(0), name_); }
  int Integer() const override {
    const double value = Number();
    if (value != std::round(value)) Fail(name_ + " must be a whole number", "a whole number");
    return static_cast<int>(value);
  }
  bool Boolean() const override { NotANumberKey(); }
  std::string String() const override { NotANumberKey(); }
  std::string Choice() const override { NotANumberKey(); }
  std::size_t ArraySize(const std::string& expected) const override {
    if (!array_) Fail(name_ + " must be " + expected, expected, InputProblem::kWrongType);
    return values_.size();
  }
  double NumberAt(std::size_t index) const override {
    return Bounded(values_.at(index), name_ + "[" + std::to_string(index) + "]");
  }
  [[noreturn]] void Fail(const std::string& message, const std::string& allowed,
                         InputProblem problem = InputProblem::kBadValue) const override {
    throw InputError(problem, {"design"}, name_, message, allowed);
  }

 private:
  [[noreturn]] void NotANumberKey() const { Fail(name_ + " is not a number key", "a number"); }
  // The key table's range check, as the scenario reader's.
  double Bounded(double value, const std::string& name) const {
    if (const auto error = NumberOutOfRange(spec_, name, value)) {
      Fail(error->message, error->allowed);
    }
    return value;
  }

  const KeySpec& spec_;
  std::string name_;
  std::vector<double> values_;
  bool array_;
};

// The current values of a number-array key in `config` (empty if it has none).
std::vector<double> ArrayValues(const KeySpec& spec, const ScenarioConfig& config) {
  std::vector<double> values;
  if (spec.write == nullptr) return values;
  const std::optional<std::string> text = spec.write(config);
  if (!text) return values;
  const toml::table table = toml::parse("v = " + *text);
  if (const toml::array* array = table["v"].as_array()) {
    for (const toml::node& element : *array) values.push_back(element.value<double>().value_or(0.0));
  }
  return values;
}

// Reads the OPT file; every failure names the file, line and field.
class OptimizeReader : public ScenarioOverrides {
 public:
  explicit OptimizeReader(std::string source) : ScenarioOverrides(std::move(source)) {}

  OptimizeConfig Read(const std::string& toml_text);

 private:
  [[noreturn]] void Bad(const toml::node* where, const std::string& field,
                        const std::string& message, const std::string& allowed) const {
    std::string place = source_;
    if (where != nullptr && where->source().begin.line > 0) {
      place += ":" + std::to_string(where->source().begin.line);
    }
    throw FieldError(place + ": " + field + ": " + message, field, allowed);
  }
  void RejectUnknown(const toml::table& table, const std::string& prefix,
                     const std::vector<std::string>& allowed) const;
  const toml::node* Required(const toml::table& table, const std::string& prefix,
                             const std::string& name) const {
    const toml::node* node = table.get(name);
    if (node == nullptr) Bad(&table, prefix + name, "is required", "a value");
    return node;
  }
  double Number(const toml::table& table, const std::string& prefix, const std::string& name,
                std::optional<double> fallback = std::nullopt) const;
  int Integer(const toml::table& table, const std::string& prefix, const std::string& name,
              int fallback, int lowest, int highest) const;
  std::string Text(const toml::table& table, const std::string& prefix, const std::string& name,
                   std::optional<std::string> fallback = std::nullopt) const;
  DesignKey ReadKey(const toml::table& table, const std::string& field,
                    const ScenarioConfig& base) const;
  // lower < upper, both inside the key's own range (every design of the
  // box is a scenario).
  void ReadBounds(const toml::table& table, const std::string& prefix, const DesignKey& key,
                  const ScenarioConfig& base, double* lower, double* upper) const;
  const toml::table& TableAt(const toml::node& node, const std::string& field) const {
    const toml::table* table = node.as_table();
    if (table == nullptr) Bad(&node, field, "must be a table", "a table");
    return *table;
  }
  // The steps of Read, one per part of the file, in its order: each reads
  // its part into `config`, the parts before it already read.
  void ReadBaseAndSet(const toml::table& root, OptimizeConfig& config);
  void ReadVariables(const toml::table& root, OptimizeConfig& config) const;
  void ReadSum(const toml::node& node, OptimizeConfig& config) const;
  void ReadObjectiveAndConstraints(const toml::table& root, OptimizeConfig& config) const;
  void ReadAlgorithm(const toml::table& root, OptimizeConfig& config) const;
  void ReadControllers(const toml::node& node, OptimizeConfig& config) const;
};

void OptimizeReader::RejectUnknown(const toml::table& table, const std::string& prefix,
                                   const std::vector<std::string>& allowed) const {
  for (auto&& [key, node] : table) {
    if (std::find(allowed.begin(), allowed.end(), key.str()) != allowed.end()) continue;
    std::string names;
    for (const std::string& name : allowed) names += (names.empty() ? "" : ", ") + name;
    Bad(&node, prefix + std::string(key.str()), "unknown key (allowed: " + names + ")", names);
  }
}

double OptimizeReader::Number(const toml::table& table, const std::string& prefix,
                              const std::string& name, std::optional<double> fallback) const {
  const toml::node* node = table.get(name);
  if (node == nullptr && fallback) return *fallback;
  if (node == nullptr) Required(table, prefix, name);
  const std::optional<double> value =
      node->is_integer() || node->is_floating_point() ? node->value<double>() : std::nullopt;
  if (!value || !std::isfinite(*value)) Bad(node, prefix + name, "must be a finite number", "a finite number");
  return *value;
}

int OptimizeReader::Integer(const toml::table& table, const std::string& prefix,
                            const std::string& name, int fallback, int lowest, int highest) const {
  const toml::node* node = table.get(name);
  if (node == nullptr) return fallback;
  const std::string allowed = "a whole number in [" + std::to_string(lowest) + ", " +
                              std::to_string(highest) + "]";
  if (!node->is_integer()) Bad(node, prefix + name, "must be " + allowed, allowed);
  const long long value = node->as_integer()->get();
  if (value < lowest || value > highest) {
    Bad(node, prefix + name, "must be " + allowed + " (got " + std::to_string(value) + ")", allowed);
  }
  return static_cast<int>(value);
}

std::string OptimizeReader::Text(const toml::table& table, const std::string& prefix,
                                 const std::string& name,
                                 std::optional<std::string> fallback) const {
  const toml::node* node = table.get(name);
  if (node == nullptr && fallback) return *fallback;
  if (node == nullptr) Required(table, prefix, name);
  if (!node->is_string()) Bad(node, prefix + name, "must be a string", "a string");
  return node->as_string()->get();
}

DesignKey OptimizeReader::ReadKey(const toml::table& table, const std::string& prefix,
                                  const ScenarioConfig& base) const {
  const std::string field = prefix + "key";
  const std::string allowed =
      "a number key of the scenario (ipmc-swim keys), or NAME[i] of a number-array key";
  DesignKey key;
  key.name = Text(table, prefix, "key");
  key.key = key.name;
  const toml::node* node = table.get("key");
  const std::string::size_type open = key.name.find('[');
  if (open != std::string::npos) {
    const std::optional<long> index =
        key.name.back() == ']'
            ? ParseInteger(key.name.substr(open + 1, key.name.size() - open - 2))
            : std::nullopt;
    if (!index || *index < 0) Bad(node, field, "'" + key.name + "' is not NAME[i]", allowed);
    key.key = key.name.substr(0, open);
    key.element = static_cast<int>(*index);
  }
  const KeySpec* spec = FindScenarioKey(key.key);
  const KeyType type = key.element >= 0 ? KeyType::kNumberArray : KeyType::kNumber;
  if (spec == nullptr || spec->type != type || spec->read == nullptr) {
    Bad(node, field, "'" + key.name + "' is not " + allowed, allowed);
  }
  if (const KeyCondition* failed = FailedCondition(*spec, base)) {
    Bad(node, field,
        "'" + key.name + "' applies only with " + failed->selector + " = \"" + failed->value + "\"",
        std::string(failed->selector) + " = \"" + failed->value + "\"");
  }
  if (key.element >= 0 &&
      key.element >= static_cast<int>(ArrayValues(*spec, base).size())) {
    Bad(node, field,
        "the base scenario's " + key.key + " has no element " + std::to_string(key.element) +
            " (set the whole array in [set])",
        "an element the base has");
  }
  return key;
}

void OptimizeReader::ReadBounds(const toml::table& table, const std::string& prefix,
                                const DesignKey& key, const ScenarioConfig& base, double* lower,
                                double* upper) const {
  *lower = Number(table, prefix, "lower");
  *upper = Number(table, prefix, "upper");
  if (!(*lower < *upper)) {
    Bad(table.get("upper"), prefix + "upper", "must be > lower (" + FormatShortest(*lower) + ")",
        "> lower");
  }
  for (const char* side : {"lower", "upper"}) {
    try {
      DesignScenario(base, {key}, {std::string(side) == "lower" ? *lower : *upper});
    } catch (const InputError& error) {
      Bad(table.get(side), prefix + side, "outside the key's range: " + error.message(),
          error.allowed());
    } catch (const FieldError& error) {
      Bad(table.get(side), prefix + side, std::string("refused by the scenario: ") + error.what(),
          error.allowed());
    }
  }
}

OptimizeConfig OptimizeReader::Read(const std::string& toml_text) {
  const toml::table root = ParseToml(toml_text, source_);
  RejectUnknown(root, "",
                {kBase, kSet, kVariable, kSum, kObjective, kConstraint, kAlgorithm, kControllers});
  OptimizeConfig config;
  config.source = source_;
  ReadBaseAndSet(root, config);
  ReadVariables(root, config);
  if (const toml::node* node = root.get(kSum)) ReadSum(*node, config);
  ReadObjectiveAndConstraints(root, config);
  ReadAlgorithm(root, config);
  if (const toml::node* node = root.get(kControllers)) ReadControllers(*node, config);
  return config;
}

// The base and [set], parsed once.
void OptimizeReader::ReadBaseAndSet(const toml::table& root, OptimizeConfig& config) {
  fs::path path(Text(root, "", kBase));
  if (path.is_relative()) path = fs::path(source_).parent_path() / path;
  config.base_path = path.lexically_normal().string();
  std::error_code ignored;
  if (!fs::is_regular_file(config.base_path, ignored)) {
    Bad(root.get(kBase), kBase, "cannot open '" + config.base_path + "'", "a scenario file");
  }
  LoadBase(config.base_path);
  std::vector<ScenarioOverride> set;
  if (const toml::node* node = root.get(kSet)) FlattenOverrides(TableAt(*node, kSet), "", &set);
  std::vector<const ScenarioOverride*> overrides;
  for (const ScenarioOverride& entry : set) overrides.push_back(&entry);
  RejectRepeatedKeys(overrides);
  OverriddenScenario read = ReadScenario(overrides);
  if (read.fatal) throw *read.fatal;
  if (read.failure) throw *read.failure;
  config.base = std::move(*read.scenario);
  config.links = ScenarioLinkCount(config.base);
}

// [[variable]]
void OptimizeReader::ReadVariables(const toml::table& root, OptimizeConfig& config) const {
  const toml::array* variables = root[kVariable].as_array();
  if (variables == nullptr || variables->empty() || !variables->is_array_of_tables()) {
    Bad(root.get(kVariable), kVariable, "one or more [[variable]] tables are required",
        "[[variable]] tables");
  }
  std::set<std::string> names;
  for (size_t i = 0; i < variables->size(); ++i) {
    const std::string prefix = std::string(kVariable) + "[" + std::to_string(i + 1) + "].";
    const toml::table& table = *variables->get(i)->as_table();
    RejectUnknown(table, prefix, {"key", "lower", "upper", "initial"});
    DesignVariable variable;
    variable.key = ReadKey(table, prefix, config.base);
    if (!names.insert(variable.key.name).second) {
      Bad(table.get("key"), prefix + "key", "'" + variable.key.name + "' is a variable twice",
          "each key once");
    }
    ReadBounds(table, prefix, variable.key, config.base, &variable.lower, &variable.upper);
    variable.initial = Number(table, prefix, "initial");
    if (!(variable.initial >= variable.lower && variable.initial <= variable.upper)) {
      const std::string allowed =
          "[" + FormatShortest(variable.lower) + ", " + FormatShortest(variable.upper) + "]";
      Bad(table.get("initial"), prefix + "initial",
          "must be in " + allowed + " (got " + FormatShortest(variable.initial) + ")", allowed);
    }
    config.variables.push_back(std::move(variable));
  }
}

// [sum]
void OptimizeReader::ReadSum(const toml::node& node, OptimizeConfig& config) const {
  const std::string prefix = std::string(kSum) + ".";
  const toml::table& table = TableAt(node, kSum);
  RejectUnknown(table, prefix, {"key", "total", "lower", "upper", "of"});
  DesignSum sum;
  sum.key = ReadKey(table, prefix, config.base);
  const bool is_variable =
      std::any_of(config.variables.begin(), config.variables.end(),
                  [&](const DesignVariable& v) { return v.key.name == sum.key.name; });
  if (is_variable) {
    Bad(table.get("key"), prefix + "key", "'" + sum.key.name + "' is a variable too",
        "a key that is not a variable");
  }
  sum.total = Number(table, prefix, "total");
  ReadBounds(table, prefix, sum.key, config.base, &sum.lower, &sum.upper);
  if (const toml::node* of = table.get("of")) {
    const toml::array* array = of->as_array();
    if (array == nullptr || array->empty()) {
      Bad(of, prefix + "of", "must be an array of variable keys", "variable keys");
    }
    for (const toml::node& element : *array) {
      const std::optional<std::string> name = element.value<std::string>();
      const auto at = std::find_if(config.variables.begin(), config.variables.end(),
                                   [&](const DesignVariable& v) { return name && v.key.name == *name; });
      if (at == config.variables.end()) {
        Bad(of, prefix + "of", "'" + name.value_or("?") + "' is not a variable", "variable keys");
      }
      sum.of.push_back(static_cast<int>(at - config.variables.begin()));
    }
  } else {
    for (size_t i = 0; i < config.variables.size(); ++i) sum.of.push_back(static_cast<int>(i));
  }
  double initial = sum.total;
  for (int i : sum.of) initial -= config.variables[i].initial;
  if (!(initial >= sum.lower && initial <= sum.upper)) {
    const std::string allowed = "[" + FormatShortest(sum.lower) + ", " + FormatShortest(sum.upper) + "]";
    Bad(&node, prefix + "total",
        "the initial point gives " + sum.key.name + " = " + FormatShortest(initial) +
            ", outside " + allowed,
        "an initial point with " + sum.key.name + " in " + allowed);
  }
  config.sum = std::move(sum);
}

// [objective] and [[constraint]]
void OptimizeReader::ReadObjectiveAndConstraints(const toml::table& root,
                                                 OptimizeConfig& config) const {
  const std::vector<std::string> metrics = MetricNames(config.links);
  std::string metric_list;
  for (const std::string& name : metrics) metric_list += (metric_list.empty() ? "" : ", ") + name;
  auto read_metric = [&](const toml::table& table, const std::string& prefix) {
    const std::string metric = Text(table, prefix, "metric");
    if (std::find(metrics.begin(), metrics.end(), metric) == metrics.end()) {
      Bad(table.get("metric"), prefix + "metric", "unknown metric '" + metric + "' (one of " +
          metric_list + ")", metric_list);
    }
    return metric;
  };
  {
    const toml::node* node = root.get(kObjective);
    if (node == nullptr) Bad(&root, kObjective, "is required", "an [objective] table");
    const std::string prefix = std::string(kObjective) + ".";
    const toml::table& table = TableAt(*node, kObjective);
    RejectUnknown(table, prefix, {"metric", "sense"});
    config.objective = read_metric(table, prefix);
    const std::string sense = Text(table, prefix, "sense");
    if (sense != "maximize" && sense != "minimize") {
      Bad(table.get("sense"), prefix + "sense", "must be maximize or minimize (got '" + sense + "')",
          "maximize, minimize");
    }
    config.maximize = sense == "maximize";
  }
  if (const toml::node* node = root.get(kConstraint)) {
    const toml::array* array = node->as_array();
    if (array == nullptr || !array->is_array_of_tables()) {
      Bad(node, kConstraint, "must be [[constraint]] tables", "[[constraint]] tables");
    }
    for (size_t i = 0; i < array->size(); ++i) {
      const std::string prefix = std::string(kConstraint) + "[" + std::to_string(i + 1) + "].";
      const toml::table& table = *array->get(i)->as_table();
      RejectUnknown(table, prefix, {"metric", "at_most", "at_least"});
      DesignConstraint constraint;
      constraint.metric = read_metric(table, prefix);
      const bool at_most = table.contains("at_most"), at_least = table.contains("at_least");
      if (at_most == at_least) {
        Bad(&table, prefix + "at_most", "give one of at_most and at_least", "at_most or at_least");
      }
      constraint.bound.at_most = at_most;
      constraint.bound.bound = Number(table, prefix, at_most ? "at_most" : "at_least");
      config.constraints.push_back(std::move(constraint));
    }
  }
}

// [algorithm]
void OptimizeReader::ReadAlgorithm(const toml::table& root, OptimizeConfig& config) const {
  toml::table defaults;
  const toml::node* algorithm_node = root.get(kAlgorithm);
  const toml::table& algorithm = algorithm_node ? TableAt(*algorithm_node, kAlgorithm) : defaults;
  const std::string prefix = std::string(kAlgorithm) + ".";
  RejectUnknown(algorithm, prefix,
                {"name", "max_evaluations", "xtol_rel", "ftol_rel", "multistart", "penalty",
                 "failed_objective"});
  const std::string name = Text(algorithm, prefix, "name", std::string("cobyla"));
  const std::vector<std::string>& algorithms = AlgorithmNames();
  const auto at = std::find(algorithms.begin(), algorithms.end(), name);
  if (at == algorithms.end()) {
    Bad(algorithm.get("name"), prefix + "name",
        "unknown algorithm '" + name + "' (cobyla, bobyqa or subplex)", "cobyla, bobyqa, subplex");
  }
  config.algorithm = static_cast<OptimizeAlgorithm>(at - algorithms.begin());
  config.max_evaluations =
      Integer(algorithm, prefix, "max_evaluations", config.max_evaluations, 1, kMaxEvaluations);
  config.multistart = Integer(algorithm, prefix, "multistart", 0, 0, kMaxStarts);
  config.xtol_rel = Number(algorithm, prefix, "xtol_rel", config.xtol_rel);
  config.ftol_rel = Number(algorithm, prefix, "ftol_rel", config.ftol_rel);
  for (const char* field : {"xtol_rel", "ftol_rel"}) {
    const double value = std::string(field) == "xtol_rel" ? config.xtol_rel : config.ftol_rel;
    if (value < 0.0) Bad(algorithm.get(field), prefix + field, "must be >= 0", ">= 0");
  }
  config.penalty = Number(algorithm, prefix, "penalty", config.penalty);
  if (!(config.penalty > 0.0)) Bad(algorithm.get("penalty"), prefix + "penalty", "must be > 0", "> 0");
  config.failed_objective = Number(algorithm, prefix, "failed_objective", 0.0);
}

// [controllers]
void OptimizeReader::ReadControllers(const toml::node& node, OptimizeConfig& config) const {
  const toml::table& controllers = TableAt(node, kControllers);
  const std::string where = std::string(kControllers) + ".";
  RejectUnknown(controllers, where, {"retune"});
  if (const toml::node* retune = controllers.get("retune")) {
    if (!retune->is_boolean()) Bad(retune, where + "retune", "must be true or false", "true or false");
    config.retune_controllers = retune->as_boolean()->get();
  }
  if (config.retune_controllers && config.base.controller.kind == ControllerKind::kFractional &&
      config.base.controller.fractional.realisation != FractionalRealisation::kOustaloup) {
    Bad(controllers.get("retune"), where + "retune",
        "needs the base's controller.realisation = \"oustaloup\" (eq. 15 fixes the order)",
        "false with realisation eq15");
  }
}

}  // namespace

DriverProblem OptimizeConfig::Problem() const {
  DriverProblem problem;
  static_cast<DriverSettings&>(problem) = *this;
  for (const DesignVariable& variable : variables) {
    problem.lower.push_back(variable.lower);
    problem.upper.push_back(variable.upper);
    problem.initial.push_back(variable.initial);
  }
  if (sum) problem.sum = EliminatedSum{sum->total, sum->of, sum->lower, sum->upper};
  for (const DesignConstraint& constraint : constraints) problem.constraints.push_back(constraint.bound);
  return problem;
}

std::vector<DesignKey> OptimizeConfig::Keys() const {
  std::vector<DesignKey> keys;
  for (const DesignVariable& variable : variables) keys.push_back(variable.key);
  if (sum) keys.push_back(sum->key);
  return keys;
}

std::vector<std::string> MetricNames(int links) {
  std::vector<std::string> names;
  for (int q = 1; q <= links; ++q) {
    for (const char* result : columns::kLinkResults) names.push_back(columns::LinkResult(q, result));
  }
  for (const char* result : columns::kSwimResults) names.push_back(result);
  for (const std::string& warning : RunWarningColumns()) names.push_back(warning);
  return names;
}

OptimizeConfig ParseOptimizeFile(const std::string& toml_text, const std::string& source) {
  OptimizeReader reader(source);
  return reader.Read(toml_text);
}

OptimizeConfig LoadOptimizeFile(const std::string& path) {
  return ParseOptimizeFile(ReadTextFile(path, "optimisation file"), path);
}

ScenarioConfig DesignScenario(const ScenarioConfig& base, const std::vector<DesignKey>& keys,
                              const std::vector<double>& x) {
  ScenarioConfig config = base;
  for (size_t i = 0; i < keys.size(); ++i) {
    const KeySpec& spec = *FindScenarioKey(keys[i].key);
    if (keys[i].element < 0) {
      spec.read(DesignValue(spec, {x[i]}, false), config);
    } else {
      std::vector<double> values = ArrayValues(spec, config);
      values.at(keys[i].element) = x[i];
      spec.read(DesignValue(spec, values, true), config);
    }
  }
  // The Configs' own checks, as the scenario reader runs them.
  config.controller.Validate();
  config.waveform.Validate();
  return config;
}

}  // namespace ipmc
