// What the ipmc_swim Python module's bindings share: Python values as TOML
// (scenario keys), JSON documents and vectors as Python objects and numpy
// arrays, keyword options read strictly, progress reported to a Python
// callable from code that runs without the GIL, and MuJoCo's warnings
// turned into Python warnings.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <future>
#include <optional>
#include <thread>
#include <utility>
#include <functional>
#include <limits>
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

// A path argument (str or os.PathLike) as text; TypeError naming `what`
// for another type, std::invalid_argument for '' or a NUL byte (the system
// would end the path there and name another file).
std::string PathText(const py::handle& path, const std::string& what);

// What a value of C++ type T is in Python's words, for messages: "an int
// (within [-2147483648, 2147483647])", "a number (int or float)", "a str",
// "a bool", "a list of ...".
template <typename T>
struct IsVector : std::false_type {};
template <typename T>
struct IsVector<std::vector<T>> : std::true_type {};

template <typename T>
std::string ExpectedType(bool plural = false) {
  const std::string s = plural ? "s" : "";
  const std::string a = plural ? "" : "a ";
  if constexpr (std::is_same_v<T, bool>) {
    return a + "bool" + s;
  } else if constexpr (std::is_integral_v<T>) {
    return (plural ? "" : "an ") + std::string("int") + s + " (within [" +
           std::to_string(std::numeric_limits<T>::min()) + ", " +
           std::to_string(std::numeric_limits<T>::max()) + "])";
  } else if constexpr (std::is_floating_point_v<T>) {
    return a + "number" + s + " (int or float)";
  } else if constexpr (std::is_same_v<T, std::string>) {
    return a + "str" + s;
  } else if constexpr (IsVector<T>::value) {
    return "a list of " + ExpectedType<typename T::value_type>(true);
  } else {
    return "of another type";
  }
}

// The type of a value and, for an int, the int: "float", "int 2**70-like
// 1180591620717411303424".
std::string Described(const py::handle& value);

// value as T, as a command line would read it: numpy scalars and arrays
// as Python numbers and lists, a bool is no number and a float no int.
// Throws py::cast_error otherwise (or for an int out of T's range).
template <typename T>
T Cast(const py::handle& given) {
  py::object value = py::reinterpret_borrow<py::object>(given);
  if (py::hasattr(value, "dtype") && py::hasattr(value, "tolist")) value = value.attr("tolist")();
  if constexpr (std::is_same_v<T, bool>) {
    if (!py::isinstance<py::bool_>(value)) throw py::cast_error();
  } else if constexpr (std::is_arithmetic_v<T>) {
    if (py::isinstance<py::bool_>(value)) throw py::cast_error();
    if constexpr (std::is_integral_v<T>) {
      if (!py::isinstance<py::int_>(value)) throw py::cast_error();
    }
  } else if constexpr (IsVector<T>::value) {
    if (!py::isinstance<py::sequence>(value) || py::isinstance<py::str>(value)) {
      throw py::cast_error();
    }
    T items;
    for (const py::handle item : value) items.push_back(Cast<typename T::value_type>(item));
    return items;
  }
  return value.cast<T>();
}

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
    const py::handle given = options_[key.c_str()];
    try {
      *value = Cast<T>(given);
    } catch (const py::cast_error&) {
      throw py::type_error(function_ + "(): " + key + " must be " + ExpectedType<T>() + " (got " +
                           Described(given) + ")");
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

// The first steps of every command's binding: the keywords read by the
// command's option table (ReadTableOptions) into `command`, which holds
// what the call's own arguments set, and any other keyword refused.
template <typename Spec>
Spec ReadCommandKeywords(Options& options, const OptionTable<Spec>& table, Spec command = Spec()) {
  ReadTableOptions(options, table, &command);
  options.RejectUnknown();
  return command;
}

// Reports progress, done of total (simulated seconds, points), to a Python
// callable `callback(done, total)` (or None) first at once, then at most
// every 0.2 s of wall time, and raises pending signals when called in the
// main thread. Report is called without the GIL, from any thread
// (Interruptible's worker); it throws py::error_already_set when
// the callback raises. Made and destroyed with the GIL held.
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

// The whole binding of a command that reports no progress: `function`'s
// keywords read (ReadCommandKeywords), then run(command, given), where
// given(name) tells whether the call named that table option
// (GivenKeywords), with the GIL released.
template <typename Spec, typename Run>
auto RunCommandWithoutGil(const std::string& function, const py::dict& kwargs,
                          const OptionTable<Spec>& table, Run&& run) {
  Options options(function, kwargs);
  const Spec command = ReadCommandKeywords(options, table);
  const std::function<bool(const std::string&)> given = GivenKeywords(options, table);
  return WithoutGil([&] { return run(command, given); });
}

// Runs work(stop) without the GIL on a thread of its own while the
// calling thread waits, looking for Python's signals every 0.1 s (in the
// main thread; Python handles signals only there). When a handler raises
// (Ctrl-C's KeyboardInterrupt), `stop` becomes true, the work ends at its
// next safe point (a run's recorded sample, a bench's sample, between a
// sweep's points, before a design's next evaluation of J: it returns or
// throws, it does not matter which), and the
// handler's exception is raised then, with nothing written. Otherwise the
// work's result is returned or its exception rethrown. MuJoCo's warnings
// are emitted after. work(const std::atomic<bool>& stop) may report
// Progress (which takes the GIL).
template <typename F>
auto Interruptible(F&& work) {
  using Result = decltype(work(std::declval<const std::atomic<bool>&>()));
  constexpr auto kSignalInterval = std::chrono::milliseconds(100);
  std::atomic<bool> stop{false};
  std::packaged_task<Result()> task([&] { return work(stop); });
  std::future<Result> done = task.get_future();
  std::optional<py::error_already_set> raised;
  {
    py::gil_scoped_release release;
    std::thread worker(std::move(task));
    while (done.wait_for(kSignalInterval) != std::future_status::ready) {
      if (stop) continue;
      py::gil_scoped_acquire gil;
      if (PyErr_CheckSignals() != 0) {
        raised.emplace();
        stop = true;
      }
    }
    worker.join();
  }
  EmitMujocoWarnings();
  if (raised) throw std::move(*raised);
  return done.get();
}

// What a run's observer throws at its safe point once `stop` is set, to
// end the run (Interruptible raises the signal's exception instead).
struct StopRequested {};
inline void ThrowIfStopRequested(const std::atomic<bool>& stop) {
  if (stop) throw StopRequested{};
}

// The module's parts.
void BindRuns(py::module_& m);
void BindAnalysis(py::module_& m);
void BindSimulation(py::module_& m);
void BindPlot(py::module_& m);
void BindOptimize(py::module_& m);  // bind_optimize.cc

}  // namespace ipmc::python
