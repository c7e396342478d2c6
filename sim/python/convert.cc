#include "sim/python/convert.h"

#include "sim/batch/sweep.h"
#include "sim/core/scenario_keys.h"

#include <mujoco/mujoco.h>

#include <cstdint>
#include <limits>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace ipmc::python {
namespace {

constexpr double kProgressInterval_s = 0.2;
// The messages' name for a scenario given as a dict.
constexpr char kScenarioDict[] = "scenario dict";

std::string TypeName(const py::handle& value) {
  return py::str(py::type::of(value).attr("__name__"));
}

bool IsNumpyBool(const py::handle& value) { return TypeName(value) == "bool_"; }

toml::array TomlArray(const py::handle& sequence, const std::string& key);

bool IsNumpyScalar(const py::handle& value) {
  return py::hasattr(value, "dtype") && py::hasattr(value, "item") && py::hasattr(value, "ndim") &&
         value.attr("ndim").cast<int>() == 0;
}

// One value; dicts become tables, sequences arrays.
template <typename Insert>
void InsertToml(const py::handle& value, const std::string& key, Insert&& insert) {
  if (IsNumpyScalar(value) && !IsNumpyBool(value)) {
    // np.float32(2), np.int64(3): as the Python number they hold.
    InsertToml(value.attr("item")(), key, insert);
  } else if (py::hasattr(value, "dtype") && py::hasattr(value, "tolist") &&
             !IsNumpyScalar(value)) {
    insert(TomlArray(value, key));  // an array (before ints: a 1-element one has __index__)
  } else if (py::isinstance<py::bool_>(value) || IsNumpyBool(value)) {
    insert(value.cast<bool>());
  } else if (py::isinstance<py::int_>(value) || (!py::isinstance<py::float_>(value) &&
                                                 PyIndex_Check(value.ptr()))) {
    try {
      insert(value.cast<std::int64_t>());
    } catch (const py::cast_error&) {
      throw py::type_error(key + ": the int " + std::string(py::str(value)) +
                           " is beyond a scenario integer's range (a 64-bit int, at most " +
                           std::to_string(std::numeric_limits<std::int64_t>::max()) + ")");
    }
  } else if (py::isinstance<py::float_>(value)) {
    insert(value.cast<double>());
  } else if (py::isinstance<py::str>(value)) {
    insert(value.cast<std::string>());
  } else if (py::hasattr(value, "__fspath__")) {
    insert(PathText(value, key));
  } else if (py::isinstance<py::dict>(value)) {
    insert(TomlTable(value.cast<py::dict>(), key));
  } else if (py::isinstance<py::sequence>(value) || py::hasattr(value, "tolist")) {
    insert(TomlArray(value, key));
  } else {
    throw py::type_error(key + ": a scenario value must be a bool, number, string, list or dict " +
                         "(got " + TypeName(value) + ")");
  }
}

toml::array TomlArray(const py::handle& sequence, const std::string& key) {
  const py::object items = py::hasattr(sequence, "tolist")
                               ? sequence.attr("tolist")()
                               : py::reinterpret_borrow<py::object>(sequence);
  toml::array array;
  size_t index = 0;
  for (const py::handle item : items) {
    InsertToml(item, key + "[" + std::to_string(index++) + "]",
               [&](auto&& node) { array.push_back(std::forward<decltype(node)>(node)); });
  }
  return array;
}

template <typename Json>
py::object JsonToPython(const Json& json) {
  switch (json.type()) {
    case nlohmann::json::value_t::null:
      return py::none();
    case nlohmann::json::value_t::boolean:
      return py::bool_(json.template get<bool>());
    case nlohmann::json::value_t::number_integer:
      return py::int_(json.template get<std::int64_t>());
    case nlohmann::json::value_t::number_unsigned:
      return py::int_(json.template get<std::uint64_t>());
    case nlohmann::json::value_t::number_float:
      return py::float_(json.template get<double>());
    case nlohmann::json::value_t::string:
      return py::str(json.template get<std::string>());
    case nlohmann::json::value_t::array: {
      py::list list;
      for (const auto& element : json) list.append(JsonToPython(element));
      return std::move(list);
    }
    case nlohmann::json::value_t::object: {
      py::dict dict;
      for (const auto& [key, value] : json.items()) dict[py::str(key)] = JsonToPython(value);
      return std::move(dict);
    }
    default:
      throw py::type_error("JSON value of an unexpected type");
  }
}

template <typename T>
py::array_t<T> ArrayOf(const std::vector<T>& values) {
  py::array_t<T> array(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), array.mutable_data());
  return array;
}

// MuJoCo's warnings since the last call, from any thread.
struct MujocoWarningLog {
  std::mutex mutex;
  std::vector<std::string> messages;
};

MujocoWarningLog& WarningLog() {
  static MujocoWarningLog* log = new MujocoWarningLog;  // lives as long as the hook
  return *log;
}

void CollectMujocoWarning(const char* message) {
  MujocoWarningLog& log = WarningLog();
  std::lock_guard<std::mutex> lock(log.mutex);
  log.messages.emplace_back(message);
}

}  // namespace

namespace {

// A bool given for a scenario key that takes a number: a TypeError, as for
// the keyword arguments (a bool is no number).
void RefuseBoolForNumber(const std::string& name, const py::handle& value) {
  if (!py::isinstance<py::bool_>(value) && !IsNumpyBool(value)) return;
  const KeySpec* spec = FindScenarioKey(name);
  if (spec == nullptr) return;
  if (spec->type == KeyType::kInteger) {
    throw py::type_error(name + " must be an int (got bool; a bool is no number)");
  }
  if (spec->type == KeyType::kNumber || spec->type == KeyType::kNumberArray) {
    throw py::type_error(name + " must be a number (int or float) (got bool; a bool is no number)");
  }
}

}  // namespace

toml::table TomlTable(const py::dict& dict, const std::string& where) {
  toml::table table;
  for (const auto& [key, value] : dict) {
    if (!py::isinstance<py::str>(key)) {
      throw py::type_error(where + ": scenario keys must be strings (got " + TypeName(key) + ")");
    }
    const std::string name = key.cast<std::string>();
    RefuseBoolForNumber(name, value);
    InsertToml(value, name, [&](auto&& node) {
      table.insert_or_assign(name, std::forward<decltype(node)>(node));
    });
  }
  return table;
}

nlohmann::json Json(const py::dict& dict, const std::string& where) {
  const toml::table table = TomlTable(dict, where);  // the same values, checked
  std::ostringstream text;
  text << toml::json_formatter{table};
  return nlohmann::json::parse(text.str());
}

ScenarioArgument ReadScenarioArgument(const py::object& scenario, const py::dict& overrides,
                                      const std::string& function) {
  ScenarioArgument argument;
  if (py::isinstance<py::dict>(scenario)) {
    py::dict whole;
    for (const auto& [key, value] : scenario.cast<py::dict>()) whole[key] = value;
    for (const auto& [key, value] : overrides) {
      if (whole.contains(key)) {
        throw py::type_error(function + "(): " + std::string(py::str(key)) +
                             " is given both in the scenario dict and as an override");
      }
      whole[key] = value;
    }
    argument.scenario = ScenarioWithOverrides("", TomlTable(whole, kScenarioDict), kScenarioDict);
    argument.inputs = {{"scenario", Json(whole, kScenarioDict)}};
    return argument;
  }
  const std::string path = PathText(scenario, function + "(): scenario");
  argument.scenario =
      ScenarioWithOverrides(path, TomlTable(overrides, "overrides"), path + " overrides");
  argument.inputs = {{"scenario", path}};
  if (!overrides.empty()) argument.inputs["overrides"] = Json(overrides, "overrides");
  return argument;
}

py::object ToPython(const nlohmann::json& json) { return JsonToPython(json); }
py::object ToPython(const nlohmann::ordered_json& json) { return JsonToPython(json); }

py::array_t<double> Array(const std::vector<double>& values) { return ArrayOf(values); }
py::array_t<std::complex<double>> Array(const std::vector<std::complex<double>>& values) {
  return ArrayOf(values);
}

std::string Described(const py::handle& value) {
  std::string text = TypeName(value);
  if (py::isinstance<py::int_>(value) && !py::isinstance<py::bool_>(value)) {
    const std::string digits = py::str(value);
    text += " " + (digits.size() > 24 ? digits.substr(0, 20) + "..." : digits);
  }
  return text;
}

std::string PathText(const py::handle& path, const std::string& what) {
  if (py::isinstance<py::str>(path)) {
    const std::string text = path.cast<std::string>();
    if (text.empty()) throw std::invalid_argument(what + " must name a path (got '')");
    // The system would end the path at a NUL and name another file.
    if (const std::size_t nul = text.find('\0'); nul != std::string::npos) {
      throw std::invalid_argument(what + " must name a path without NUL bytes (got '" +
                                  text.substr(0, nul) + "\\x00...')");
    }
    return text;
  }
  if (py::hasattr(path, "__fspath__")) {
    const py::object text = path.attr("__fspath__")();
    if (py::isinstance<py::str>(text)) return PathText(text, what);
  }
  throw py::type_error(what + " must be a path (str or os.PathLike), got " + TypeName(path));
}

Options::Options(std::string function, py::dict options)
    : function_(std::move(function)), options_(std::move(options)) {}

void Options::RejectUnknown() const {
  for (const auto& [key, value] : options_) {
    const std::string name = py::str(key);
    if (known_.count(name) == 0) {
      std::string allowed;
      for (const std::string& k : known_) allowed += (allowed.empty() ? "" : ", ") + k;
      throw py::type_error(function_ + "() got an unexpected keyword argument '" + name +
                           "' (allowed: " + allowed + ")");
    }
  }
}

Progress::Progress(py::object callback, double total)
    : callback_(std::move(callback)), total_(total), last_(std::chrono::steady_clock::now()) {
  if (!callback_.is_none() && !PyCallable_Check(callback_.ptr())) {
    throw py::type_error("progress must be callable as progress(done, total) or None");
  }
}

void Progress::Report(double done, bool force) {
  const auto now = std::chrono::steady_clock::now();
  if (!force && started_ &&
      std::chrono::duration<double>(now - last_).count() < kProgressInterval_s) {
    return;
  }
  started_ = true;
  last_ = now;
  py::gil_scoped_acquire gil;
  // A call that runs its work in the calling thread sees signals here (in
  // Interruptible's worker Python reports none: the waiting thread does).
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  if (!callback_.is_none()) callback_(done, total_);
}

void InstallMujocoWarningLog() { mju_user_warning = CollectMujocoWarning; }

void EmitMujocoWarnings() {
  std::vector<std::string> messages;
  {
    MujocoWarningLog& log = WarningLog();
    std::lock_guard<std::mutex> lock(log.mutex);
    messages.swap(log.messages);
  }
  if (messages.empty()) return;
  const py::object warn = py::module_::import("warnings").attr("warn");
  for (const std::string& message : messages) {
    warn("MuJoCo: " + message, py::handle(PyExc_RuntimeWarning), 2);
  }
}

}  // namespace ipmc::python
