#include "sim/batch/sweep_gait.h"

#include <algorithm>
#include <climits>
#include <filesystem>
#include <optional>
#include <type_traits>
#include <utility>
#include <variant>

#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/io/columns.h"
#include "sim/io/toml.h"

namespace ipmc {

const std::vector<std::string> kGaitResults = {
    "period_s",     columns::kLastCycleComAlong, columns::kMeanSpeedAlong,
    "peak_lateral_tip_speed_mm_s", columns::kReynoldsTip, columns::kReynoldsSwim,
    "max_tracking_error_rad", "max_reference_rad"};

namespace {

namespace fs = std::filesystem;
using namespace sweep_keys;

template <typename T>
struct IsList : std::false_type {};
template <typename T>
struct IsList<std::vector<T>> : std::true_type {};

// A value as the table prints it (as scenario sweeps print theirs).
std::string Printed(const toml::node& node) {
  if (const auto* text = node.as_string()) return OneLine(text->get());
  if (const auto* integer = node.as_integer()) return std::to_string(integer->get());
  if (const auto* number = node.as_floating_point()) return FormatShortest(number->get());
  if (const auto* boolean = node.as_boolean()) return boolean->get() ? "true" : "false";
  std::string joined = "[";
  if (const auto* array = node.as_array()) {
    for (const toml::node& element : *array) {
      joined += (joined.size() > 1 ? ", " : "") + Printed(element);
    }
  }
  return joined + "]";
}

std::optional<double> Number(const toml::node& node) {
  if (const auto* integer = node.as_integer()) return static_cast<double>(integer->get());
  if (const auto* number = node.as_floating_point()) return number->get();
  return std::nullopt;
}

// One option set from the sweep file.
struct GaitSetting {
  std::string key;
  const toml::node* value = nullptr;
  std::uint32_t line = 0;
};

class GaitSweepReader {
 public:
  explicit GaitSweepReader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void Fail(std::uint32_t line, const std::string& message,
                         InputProblem problem = InputProblem::kBadValue,
                         const std::string& key = "") const {
    throw InputError(problem, {source_, line}, key, message);
  }

  // The option named `key`, or a failure naming the allowed ones.
  const Option<GaitCommand>& OptionOf(const std::string& where, const std::string& key,
                                      std::uint32_t line) const {
    std::string names;
    for (const Option<GaitCommand>& option : GaitOptions().options()) {
      if (option.info.name == "out") continue;
      if (option.info.name == key) return option;
      names += (names.empty() ? "" : ", ") + option.info.name;
    }
    Fail(line, where + ": unknown gait option '" + key + "' (allowed: " + names + ")",
         InputProblem::kUnknownKey, key);
  }

  // Sets the option of `setting` on `command`, as its type reads it.
  void Apply(const std::string& where, const GaitSetting& setting, GaitCommand* command) const {
    const Option<GaitCommand>& option = OptionOf(where, setting.key, setting.line);
    const toml::node& node = *setting.value;
    const std::string name = where + "." + setting.key;
    auto wrong = [&](const std::string& expected) {
      Fail(setting.line,
           name + " must be " + expected + " (got " + TomlTypeName(node.type()) + ")",
           InputProblem::kWrongType, name);
    };
    std::visit(
        [&](const auto& field) {
          auto& value = field(*command);
          using T = std::decay_t<decltype(value)>;
          if constexpr (std::is_same_v<T, bool>) {
            if (!node.is_boolean()) wrong("true or false");
            value = node.as_boolean()->get();
          } else if constexpr (std::is_same_v<T, int>) {
            const auto* integer = node.as_integer();
            if (integer == nullptr) wrong("an integer");
            if (integer->get() < INT_MIN || integer->get() > INT_MAX) {
              Fail(setting.line, name + " is beyond an integer's range", InputProblem::kBadValue,
                   name);
            }
            value = static_cast<int>(integer->get());
          } else if constexpr (std::is_same_v<T, double>) {
            const std::optional<double> number = Number(node);
            if (!number) wrong("a number");
            value = *number;
          } else if constexpr (std::is_same_v<T, std::string>) {
            if (!node.is_string()) wrong("a string");
            value = node.as_string()->get();
            if (!option.info.choices.empty() &&
                std::find(option.info.choices.begin(), option.info.choices.end(), value) ==
                    option.info.choices.end()) {
              std::string words;
              for (const std::string& choice : option.info.choices) {
                words += (words.empty() ? "" : ", ") + choice;
              }
              Fail(setting.line, name + " must be one of " + words + " (got '" + value + "')",
                   InputProblem::kBadValue, name);
            }
            if (option.info.type == OptionType::kPath && fs::path(value).is_relative()) {
              value = (fs::path(source_).parent_path() / value).lexically_normal().string();
            }
          } else if constexpr (std::is_same_v<T, std::vector<double>>) {
            const toml::array* array = node.as_array();
            if (array == nullptr) wrong("an array of numbers");
            value.clear();
            for (const toml::node& element : *array) {
              const std::optional<double> number = Number(element);
              if (!number) wrong("an array of numbers");
              value.push_back(*number);
            }
          } else {
            Fail(setting.line, name + " cannot be set in a sweep file", InputProblem::kBadValue,
                 name);
          }
        },
        option.field);
  }

  // The settings of a table, in file order.
  std::vector<GaitSetting> Settings(const toml::table& table) const {
    std::vector<GaitSetting> settings;
    for (auto&& [key, node] : table) {
      settings.push_back({std::string(key.str()), &node, key.source().begin.line});
    }
    std::sort(settings.begin(), settings.end(), [](const GaitSetting& a, const GaitSetting& b) {
      return a.line < b.line;
    });
    return settings;
  }

  SweepPlan Read(const toml::table& root);

 private:
  std::string source_;
};

SweepPlan GaitSweepReader::Read(const toml::table& root) {
  auto line_of = [&](const char* key) { return root.find(key)->first.source().begin.line; };
  if (root.contains(kBase)) {
    Fail(std::max(line_of(kBase), line_of(kGaitSweepKey)),
         "base and gait cannot be combined (a point runs a scenario or a prescribed gait)");
  }
  auto table_of = [&](const char* key) {
    const toml::table* table = root[key].as_table();
    if (table == nullptr) {
      Fail(line_of(key), std::string(key) + " must be a table", InputProblem::kWrongType, key);
    }
    return table;
  };
  GaitCommand base;
  std::vector<std::string> fixed;  // keys of [gait] and [set]
  for (const char* part : {kGaitSweepKey, kSet}) {
    if (!root.contains(part)) continue;
    for (const GaitSetting& setting : Settings(*table_of(part))) {
      Apply(part, setting, &base);
      if (part == std::string(kSet) &&
          std::find(fixed.begin(), fixed.end(), setting.key) != fixed.end()) {
        Fail(setting.line, "set." + setting.key + " is set in [gait] already");
      }
      fixed.push_back(setting.key);
    }
  }
  SweepPlan plan;
  plan.source = source_;
  plan.gait = true;
  if (root.contains(kKeepRuns)) {
    const toml::value<bool>* keep = root[kKeepRuns].as_boolean();
    if (keep == nullptr) {
      Fail(line_of(kKeepRuns), "keep_runs must be true or false", InputProblem::kWrongType,
           kKeepRuns);
    }
    plan.keep_runs = keep->get();
  }
  auto swept_once = [&](const GaitSetting& setting, const std::string& where) {
    if (std::find(fixed.begin(), fixed.end(), setting.key) != fixed.end()) {
      Fail(setting.line, where + "." + setting.key + " is set in [gait] or [set] already");
    }
  };
  // Each point: the settings it adds to the base.
  std::vector<std::vector<GaitSetting>> points;
  const bool has_grid = root.contains(kGrid), has_points = root.contains(kPoint);
  if (has_grid == has_points) {
    Fail(has_grid ? std::max(line_of(kGrid), line_of(kPoint)) : 0,
         "needs a [grid] table or [[point]] tables (one of them)");
  }
  if (has_grid) {
    std::vector<GaitSetting> axes = Settings(*table_of(kGrid));
    if (axes.empty()) Fail(line_of(kGrid), "grid must sweep at least one gait option");
    double count = 1.0;
    for (const GaitSetting& axis : axes) {
      swept_once(axis, kGrid);
      const toml::array* values = axis.value->as_array();
      if (values == nullptr || values->empty()) {
        Fail(axis.line, "grid." + axis.key + " must be a non-empty array of values",
             InputProblem::kWrongType, "grid." + axis.key);
      }
      for (const toml::node& value : *values) {
        GaitCommand check;
        Apply(kGrid, {axis.key, &value, axis.line}, &check);
      }
      plan.keys.push_back(axis.key);
      count *= static_cast<double>(values->size());
    }
    if (count > kMaxPoints) Fail(line_of(kGrid), "the grid has too many points");
    std::vector<size_t> digit(axes.size(), 0);
    for (long index = 0; index < static_cast<long>(count); ++index) {
      std::vector<GaitSetting> point;
      for (size_t k = 0; k < axes.size(); ++k) {
        point.push_back({axes[k].key, &(*axes[k].value->as_array())[digit[k]], axes[k].line});
      }
      points.push_back(std::move(point));
      for (size_t k = axes.size(); k-- > 0;) {
        if (++digit[k] < axes[k].value->as_array()->size()) break;
        digit[k] = 0;
      }
    }
  } else {
    const toml::array* tables = root[kPoint].as_array();
    if (tables == nullptr || !tables->is_array_of_tables() || tables->empty()) {
      Fail(line_of(kPoint), "point must be one or more tables of gait options ([[point]])");
    }
    for (const toml::node& node : *tables) {
      std::vector<GaitSetting> point = Settings(*node.as_table());
      for (const GaitSetting& setting : point) {
        swept_once(setting, kPoint);
        if (std::find(plan.keys.begin(), plan.keys.end(), setting.key) == plan.keys.end()) {
          plan.keys.push_back(setting.key);
        }
      }
      points.push_back(std::move(point));
    }
  }
  for (size_t index = 0; index < points.size(); ++index) {
    SweepPoint point;
    point.index = static_cast<int>(index);
    GaitCommand command = base;
    point.values.assign(plan.keys.size(), "");
    for (const GaitSetting& setting : points[index]) {
      Apply(has_grid ? kGrid : kPoint, setting, &command);
      const size_t column =
          std::find(plan.keys.begin(), plan.keys.end(), setting.key) - plan.keys.begin();
      point.values[column] = Printed(*setting.value);
    }
    point.scenario_toml = GaitCommandText(command);
    point.gait = std::move(command);
    plan.points.push_back(std::move(point));
  }
  return plan;
}

}  // namespace

SweepPlan ReadGaitSweep(const toml::table& root, const std::string& source) {
  return GaitSweepReader(source).Read(root);
}

std::string GaitCommandText(const GaitCommand& command) {
  std::string text;
  GaitCommand copy = command;
  for (const Option<GaitCommand>& option : GaitOptions().options()) {
    if (option.info.name == "out") continue;
    std::visit(
        [&](const auto& field) {
          const auto& value = field(copy);
          using T = std::decay_t<decltype(value)>;
          std::string printed;
          if constexpr (std::is_same_v<T, bool>) {
            printed = value ? "true" : "false";
          } else if constexpr (std::is_same_v<T, int>) {
            printed = std::to_string(value);
          } else if constexpr (std::is_same_v<T, double>) {
            printed = FormatShortest(value);
          } else if constexpr (std::is_same_v<T, std::string>) {
            printed = "'" + value + "'";
          } else if constexpr (IsList<T>::value) {
            printed = "[";
            for (const auto& element : value) {
              if constexpr (std::is_same_v<std::decay_t<decltype(element)>, double>) {
                printed += (printed.size() > 1 ? ", " : "") + FormatShortest(element);
              }
            }
            printed += "]";
          }
          text += option.info.name + " = " + printed + "\n";
        },
        option.field);
  }
  return text;
}

std::vector<std::string> GaitResultCells(const GaitRunResult* result) {
  if (result == nullptr) return std::vector<std::string>(kGaitResults.size(), "");
  const SwimMetrics& swim = result->swim;
  const double last_cycle = swim.per_cycle.empty() ? 0.0 : swim.per_cycle.back().com_along;
  std::vector<std::string> cells;
  for (double value : {result->period_s, last_cycle, swim.mean_speed_along_mm_s,
                       swim.peak_lateral_tip_speed_mm_s, swim.reynolds_tip, swim.reynolds_swim,
                       result->max_tracking_error_rad, result->max_reference_rad}) {
    cells.push_back(FormatShortest(value));
  }
  return cells;
}

}  // namespace ipmc
