// What the ipmc_swim Python module's bindings share: Python values as TOML
// (scenario keys), JSON documents and vectors as Python objects and numpy
// arrays, keyword options read strictly, progress reported to a Python
// callable from code that runs without the GIL, and MuJoCo's warnings
// turned into Python warnings.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <functional>
#include <variant>
#include <complex>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "sim/core/scenario.h"
#include "sim/io/option_table.h"

namespace ipmc::python {

namespace py = pybind11;

// A dict of scenario keys as a TOML table: bool, int, float, str and
// os.PathLike values, sequences as arrays, dicts as tables. Raises
// TypeError naming the key (`where` names the argument) for anything else.
toml::table TomlTable(const py::dict& dict, const std::string& where);

// A dict of scenario keys as JSON (the inputs recorded in summary.json).
nlohmann::json Json(const py::dict& dict, const std::string& where);

// A scenario argument, a scenario file's path or a dict of scenario keys,
// with keyword overrides (dotted keys, or dicts for tables), read as
// ScenarioWithOverrides (sim/core/scenario_overrides.h) reads a sweep's [set]. Errors
// in an override name "PATH overrides" (or "scenario dict") and the key.
// `inputs` records both for summary.json.
struct ScenarioArgument {
  ScenarioConfig scenario;
  nlohmann::json inputs;
};
ScenarioArgument ReadScenarioArgument(const py::object& scenario, const py::dict& overrides,
                                      const std::string& function);

// JSON documents as Python objects (dicts, lists, floats, ints, str, None).
py::object ToPython(const nlohmann::json& json);
py::object ToPython(const nlohmann::ordered_json& json);

// Copies into new one-dimensional arrays.
py::array_t<double> Array(const std::vector<double>& values);
py::array_t<std::complex<double>> Array(const std::vector<std::complex<double>>& values);

// A path argument (str or os.PathLike) as text; TypeError naming `what`.
std::string PathText(const py::handle& path, const std::string& what);

// The keyword options of one call, read with their types checked and
// unknown names refused (TypeError naming the function and the option).
class Options {
 public:
  Options(std::string function, py::dict options);

  // Reads `key` into *value if given; true if it was.
  template <typename T>
  bool Read(const std::string& key, T* value) {
    known_.insert(key);
    if (!options_.contains(key)) return false;
    try {
      *value = options_[key.c_str()].cast<T>();
    } catch (const py::cast_error&) {
      const py::handle type = py::type::of(options_[key.c_str()]);
      throw py::type_error(function_ + "(): " + key + " has the wrong type (got " +
                           std::string(py::str(type.attr("__name__"))) + ")");
    }
    return true;
  }
  // Reads a path (str or os.PathLike).
  bool ReadPath(const std::string& key, std::string* value) {
    known_.insert(key);
    if (!options_.contains(key)) return false;
    *value = PathText(options_[key.c_str()], function_ + "(): " + key);
    return true;
  }
  bool Given(const std::string& key) const { return options_.contains(key); }
  // Raises TypeError for an option no Read asked for.
  void RejectUnknown() const;

 private:
  std::string function_;
  py::dict options_;
  std::set<std::string> known_;
};

// Reads a command's options (its table, sim/io/option_table.h) from the
// keywords by their names (and their aliases, but for one-letter ones,
// which are command-line short flags); positional options are the call's
// own arguments, options of the command line alone are not read, and a
// table option left out keeps its default.
template <typename Spec>
void ReadTableOptions(Options& options, const OptionTable<Spec>& table, Spec* spec) {
  for (const Option<Spec>& option : table.options()) {
    if (option.info.positional || option.info.command_line_only) continue;
    std::vector<std::string> names = option.info.aliases;
    names.insert(names.begin(), option.info.name);
    for (const std::string& name : names) {
      if (name.size() == 1) continue;
      std::visit(
          [&](const auto& field) {
            auto& value = field(*spec);
            using T = std::decay_t<decltype(value)>;
            if constexpr (std::is_same_v<T, std::string>) {
              if (option.info.type == OptionType::kPath) {
                options.ReadPath(name, &value);
                return;
              }
            }
            options.Read(name, &value);
          },
          option.field);
    }
  }
}

// The keywords given, by their table names (an alias counts as its name).
template <typename Spec>
std::function<bool(const std::string&)> GivenKeywords(const Options& options,
                                                      const OptionTable<Spec>& table) {
  return [&options, &table](const std::string& name) {
    if (options.Given(name)) return true;
    for (const Option<Spec>& option : table.options()) {
      if (option.info.name != name) continue;
      for (const std::string& alias : option.info.aliases) {
        if (options.Given(alias)) return true;
      }
    }
    return false;
  };
}

// Reports progress, done of total (simulated seconds, points), to a Python
// callable `callback(done, total)` (or None) first at once, then at most
// every 0.2 s of wall time; at the same times raises pending signals (Ctrl-C's
// KeyboardInterrupt), so long calls can be interrupted. Report is called
// without the GIL; it throws py::error_already_set when the callback
// raises. Made and destroyed with the GIL held.
class Progress {
 public:
  Progress(py::object callback, double total);
  void Report(double done, bool force = false);

 private:
  py::object callback_;
  double total_;
  bool started_ = false;  // the first report goes through
  std::chrono::steady_clock::time_point last_;
};

// MuJoCo's warning hook is one process-wide pointer: the module points it
// at a log (once, on import), and each call turns what the log holds into
// Python RuntimeWarnings "MuJoCo: ..." when it returns.
void InstallMujocoWarningLog();
void EmitMujocoWarnings();

// Runs f() without the GIL, then emits MuJoCo's warnings.
template <typename F>
auto WithoutGil(F&& f) {
  if constexpr (std::is_void_v<decltype(f())>) {
    {
      py::gil_scoped_release release;
      f();
    }
    EmitMujocoWarnings();
  } else {
    auto result = [&] {
      py::gil_scoped_release release;
      return f();
    }();
    EmitMujocoWarnings();
    return result;
  }
}

// The module's parts.
void BindRuns(py::module_& m);
void BindAnalysis(py::module_& m);
void BindSimulation(py::module_& m);
void BindPlot(py::module_& m);

}  // namespace ipmc::python
