// Scenario files: strict TOML reading. Every table is walked and checked
// against its list of keys; each value is checked for type, finiteness and
// range before it reaches a Config, and the Configs' own Validate() runs
// last as a backstop (its FieldError is placed on the line of the key that
// set the field). Every error is an InputError, one line "FILE:LINE: key
// ...", built where it is found with its key and problem.
#include "sim/core/scenario.h"

#include <toml++/toml.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sim/core/scenario_keys.h"
#include "sim/io/error.h"
#include "sim/io/files.h"
#include "sim/core/model_generator.h"
#include "sim/io/numbers.h"
#include "sim/io/toml.h"

namespace ipmc {
namespace {

// Top level.
constexpr char kModel[] = "model";
constexpr char kLinkLengths[] = "link_lengths_mm";
constexpr int kMaxLinks = 20;
constexpr char kSegmentsPerLink[] = "segments_per_link";
constexpr char kPlants[] = "plants";
constexpr char kActuation[] = "actuation";
constexpr char kDynamics[] = "dynamics";
constexpr char kCycles[] = "cycles";
constexpr char kTimestep[] = "timestep_s";
constexpr char kController[] = "controller";
constexpr char kWaveform[] = "waveform";
constexpr char kFluid[] = "fluid";
constexpr char kOutput[] = "output";
// [controller], both kinds.
constexpr char kKind[] = "kind";
constexpr char kSampleRate[] = "sample_rate_Hz";
constexpr char kVMax[] = "v_max_V";
constexpr char kClamp[] = "clamp";
// [controller], kind = "pid".
constexpr char kKp[] = "kp";
constexpr char kKi[] = "ki";
constexpr char kKd[] = "kd";
constexpr char kDerivativeFilter[] = "derivative_filter_s";
// [controller], kind = "fractional".
constexpr char kGain[] = "gain";
constexpr char kOrder[] = "order";
constexpr char kOustaloupN[] = "oustaloup_n";
constexpr char kBand[] = "band_rad_s";
constexpr char kRealisation[] = "realisation";
// [waveform], kind = "polynomial".
constexpr char kC0[] = "c0_um";
constexpr char kC1[] = "c1_um_per_mm";
constexpr char kC2[] = "c2_um_per_mm2";
// [waveform], kind = "fractional".
constexpr char kC[] = "c_um";
constexpr char kAlpha[] = "alpha";
// [waveform], both kinds.
constexpr char kFrequency[] = "frequency_Hz";
constexpr char kWavelength[] = "wavelength_mm";
// [fluid]
constexpr char kViscosity[] = "viscosity_Pa_s";
// [output]
constexpr char kDir[] = "dir";
constexpr char kSamplesPerCycle[] = "samples_per_cycle";
constexpr char kStartRamp[] = "start_ramp_cycles";

constexpr char kPid[] = "pid";
constexpr char kFractional[] = "fractional";
constexpr char kOustaloup[] = "oustaloup";
constexpr char kPolynomial[] = "polynomial";
// Relative tolerance on "a whole number of timesteps per controller sample".
constexpr double kWholeStepsTolerance = 1e-9;

using KeyList = std::initializer_list<const char*>;

std::string TypeName(toml::node_type type) { return TomlTypeName(type); }

std::string Join(const std::vector<std::string>& keys, const char* separator) {
  std::string joined;
  for (const std::string& key : keys) {
    if (!joined.empty()) joined += separator;
    joined += key;
  }
  return joined;
}

std::string Quoted(std::string_view text) { return "\"" + std::string(text) + "\""; }

bool Contains(const std::vector<std::string>& keys, std::string_view key) {
  return std::any_of(keys.begin(), keys.end(), [&](const std::string& k) { return key == k; });
}

// The entry of the key table (sim/core/scenario_keys.h) for a key the
// reader reads; every such key is in it (the tests read each one back).
const KeySpec& Spec(const std::string& key) {
  const KeySpec* spec = FindScenarioKey(key);
  if (spec == nullptr) throw std::logic_error("scenario key " + key + " is not in the key table");
  return *spec;
}

// One value of the document: where it is and what it is called in messages.
struct Entry {
  std::string name;  // in messages: "controller.kp", "link_lengths_mm[0]"
  std::string key;   // the dotted key that holds it: "controller.kp", "link_lengths_mm"
  const toml::node* node = nullptr;
  std::uint32_t line = 0;
};

// Reads one scenario document; every failure throws InputError
// (sim/io/error.h) naming the source, the line and the key, with one line
// of text.
class ScenarioReader {
 public:
  explicit ScenarioReader(std::string source) : source_(std::move(source)) {}

  // `key`: the dotted key (or table) the message is about.
  [[noreturn]] void Fail(InputProblem problem, std::uint32_t line, const std::string& key,
                         const std::string& message, const std::string& allowed = "") const {
    throw InputError(problem, {source_, line}, key, message, allowed);
  }
  // A bad value of `entry`, which must be `allowed`.
  [[noreturn]] void FailValue(const Entry& entry, const std::string& message,
                              const std::string& allowed) const {
    Fail(InputProblem::kBadValue, entry.line, entry.key, message, allowed);
  }

  // The line a table starts on: its header, or for a table made by dotted
  // keys, its first key.
  static std::uint32_t TableLine(const toml::table& table) {
    std::uint32_t line = table.source().begin.line;
    if (line > 0) return line;
    for (auto&& [key, node] : table) {
      const std::uint32_t key_line = key.source().begin.line;
      if (key_line > 0 && (line == 0 || key_line < line)) line = key_line;
    }
    return line;
  }

  // The earliest key of `table` (`prefix` "" for the top level, else
  // "controller." etc.) that the key table does not allow there, reported
  // with the list of allowed keys.
  void RejectUnknownKeys(const toml::table& table, const std::string& prefix) const {
    const std::vector<std::string> allowed =
        ScenarioKeysUnder(prefix.empty() ? prefix : prefix.substr(0, prefix.size() - 1));
    const toml::key* unknown = nullptr;
    for (auto&& [key, node] : table) {
      if (Contains(allowed, key.str())) continue;
      if (unknown == nullptr || key.source().begin.line < unknown->source().begin.line) {
        unknown = &key;
      }
    }
    if (unknown != nullptr) {
      const std::string key = prefix + std::string(unknown->str());
      Fail(InputProblem::kUnknownKey, unknown->source().begin.line, key,
           "unknown key '" + key + "' (allowed: " + Join(allowed, ", ") + ")",
           Join(allowed, ", "));
    }
  }

  std::optional<Entry> Find(const toml::table& table, const std::string& prefix,
                            const char* key) const {
    const auto it = table.find(key);
    if (it == table.end()) return std::nullopt;
    Entry entry;
    entry.name = prefix + key;
    entry.key = entry.name;
    entry.node = &it->second;
    entry.line = it->first.source().begin.line;
    if (entry.line == 0) entry.line = it->second.source().begin.line;
    return entry;
  }

  [[noreturn]] void FailType(const Entry& entry, const std::string& expected) const {
    Fail(InputProblem::kWrongType, entry.line, entry.key,
         entry.name + " must be " + expected + " (got " + TypeName(entry.node->type()) + ")",
         expected);
  }

  // A finite number; integers are accepted.
  double Number(const Entry& entry) const {
    if (!entry.node->is_number()) FailType(entry, "a number");
    const double value = entry.node->is_integer()
                             ? static_cast<double>(entry.node->as_integer()->get())
                             : entry.node->as_floating_point()->get();
    if (!std::isfinite(value)) {
      FailValue(entry, entry.name + " must be finite (got " + FormatShortest(value) + ")",
                "finite");
    }
    return value;
  }

  // An integer in the key's bounds.
  int Integer(const Entry& entry) const {
    if (!entry.node->is_integer()) FailType(entry, "an integer");
    const KeySpec& spec = Spec(entry.key);
    const std::int64_t minimum = static_cast<std::int64_t>(spec.minimum);
    const std::int64_t maximum = static_cast<std::int64_t>(spec.maximum);
    const std::int64_t value = entry.node->as_integer()->get();
    if (value < minimum) {
      FailValue(entry, entry.name + " must be >= " + std::to_string(minimum) + " (got " +
                           std::to_string(value) + ")",
                ">= " + std::to_string(minimum));
    }
    if (value > maximum) {
      FailValue(entry, entry.name + " must be <= " + std::to_string(maximum) + " (got " +
                           std::to_string(value) + ")",
                "<= " + std::to_string(maximum));
    }
    return static_cast<int>(value);
  }

  bool Boolean(const Entry& entry) const {
    if (!entry.node->is_boolean()) FailType(entry, "a boolean");
    return entry.node->as_boolean()->get();
  }

  std::string String(const Entry& entry) const {
    if (!entry.node->is_string()) FailType(entry, "a string");
    return entry.node->as_string()->get();
  }

  // One of the key's choices (a string).
  std::string Choice(const Entry& entry) const {
    const std::string value = String(entry);
    const std::vector<std::string> choices = KeyChoices(Spec(entry.key));
    if (!Contains(choices, value)) {
      std::string allowed;
      for (const std::string& choice : choices) {
        if (!allowed.empty()) allowed += " or ";
        allowed += Quoted(choice);
      }
      FailValue(entry, entry.name + " must be " + allowed + " (got " + Quoted(value) + ")",
                allowed);
    }
    return value;
  }

  const toml::table* Table(const toml::table& root, const char* key) const {
    const std::optional<Entry> entry = Find(root, "", key);
    if (!entry) return nullptr;
    if (!entry->node->is_table()) FailType(*entry, "a table");
    return entry->node->as_table();
  }

  // A number within the key's bounds in the key table.
  double Bounded(const Entry& entry) const {
    const double value = Number(entry);
    const KeySpec& spec = Spec(entry.key);
    if (spec.lower == Bound::kClosed && !(value >= spec.minimum)) {
      FailBound(entry, value, ">= ", spec.minimum);
    }
    if (spec.lower == Bound::kOpen && !(value > spec.minimum)) {
      FailBound(entry, value, "> ", spec.minimum);
    }
    if (spec.upper == Bound::kClosed && !(value <= spec.maximum)) {
      FailBound(entry, value, "<= ", spec.maximum);
    }
    return value;
  }
  [[noreturn]] void FailBound(const Entry& entry, double value, const std::string& relation,
                              double bound) const {
    const std::string allowed = relation + FormatShortest(bound);
    FailValue(entry, entry.name + " must be " + allowed + " (got " + FormatShortest(value) + ")",
              allowed);
  }

  // Keys that belong to the other kind of a table are mistakes (a gain
  // that would be silently ignored), not settings. `selector` is the key
  // that chose the kind ("kind", or "realisation" in [controller]).
  void RejectKeysOfOtherKind(const toml::table& table, const std::string& prefix, KeyList keys,
                             const char* their_kind, const std::string& kind,
                             const char* selector = "kind") const {
    for (const char* key : keys) {
      if (const std::optional<Entry> entry = Find(table, prefix, key)) {
        Fail(InputProblem::kOtherKind, entry->line, entry->key,
             entry->name + " applies only to " + selector + " = " + Quoted(their_kind) + " (" +
                 selector + " is " + Quoted(kind) + ")");
      }
    }
  }

  // A failure about `key` of the table `table_name` (nullptr: the table
  // itself), placed on the key's line if it is there, else the table's.
  [[noreturn]] void FailInTable(const toml::table& table, const char* table_name, const char* key,
                                const std::string& message, const std::string& allowed) const {
    if (key != nullptr) {
      if (const auto entry = Find(table, std::string(table_name) + ".", key)) {
        FailValue(*entry, message, allowed);
      }
    }
    Fail(InputProblem::kBadValue, TableLine(table), table_name, message, allowed);
  }

  ScenarioConfig Read(const toml::table& root) const;

 private:
  void ReadController(const toml::table& table, ScenarioConfig* config) const;
  void ReadRealisation(const toml::table& table, FractionalIntegrator::Config* fractional) const;
  void ReadWaveform(const toml::table& table, WaveformConfig* wave) const;
  void ReadStartRamp(const toml::table& table, ScenarioConfig* config) const;
  void ReadLinkLengths(const Entry& entry, ScenarioConfig* config) const;

  std::string source_;
};

// Controller fields as the TOML keys that set them, for placing a
// Validate() message on the right line; nullptr for another field.
const char* ControllerKeyOfField(const std::string& name) {
  static const std::pair<const char*, const char*> kFieldKeys[] = {
      {"kp", kKp},
      {"ki", kKi},
      {"kd", kKd},
      {"derivative_filter_time_s", kDerivativeFilter},
      {"sample_period_s", kSampleRate},
      {"v_max", kVMax},
      {"gain", kGain},
      {"order", kOrder},
      {"oustaloup_n", kOustaloupN},
      {"w_low_rad_s", kBand},
      {"w_high_rad_s", kBand},
  };
  for (const auto& [field, key] : kFieldKeys) {
    if (name == field) return key;
  }
  return nullptr;
}

void ScenarioReader::ReadController(const toml::table& table, ScenarioConfig* config) const {
  const std::string prefix = std::string(kController) + ".";
  RejectUnknownKeys(table, prefix);

  std::string kind = kPid;
  if (const auto entry = Find(table, prefix, kKind)) kind = Choice(*entry);
  config->controller = kind == kPid ? ControllerKind::kPid : ControllerKind::kFractional;
  if (kind == kPid) {
    RejectKeysOfOtherKind(table, prefix, {kGain, kOrder, kOustaloupN, kBand, kRealisation},
                          kFractional, kind);
  } else {
    RejectKeysOfOtherKind(table, prefix, {kKp, kKi, kKd, kDerivativeFilter}, kPid, kind);
    ReadRealisation(table, &config->fractional);
  }

  if (const auto entry = Find(table, prefix, kSampleRate)) {
    config->sample_rate_Hz = Bounded(*entry);
  }
  double v_max = config->pid.v_max;
  if (const auto entry = Find(table, prefix, kVMax)) {
    v_max = Bounded(*entry);
  }
  bool clamp = config->pid.clamp_enabled;
  if (const auto entry = Find(table, prefix, kClamp)) clamp = Boolean(*entry);

  PidController::Config& pid = config->pid;
  const std::pair<const char*, double*> pid_gains[] = {
      {kKp, &pid.kp},
      {kKi, &pid.ki},
      {kKd, &pid.kd},
      {kDerivativeFilter, &pid.derivative_filter_time_s}};
  for (const auto& [key, field] : pid_gains) {
    if (const auto entry = Find(table, prefix, key)) {
      *field = Bounded(*entry);
    }
  }

  FractionalIntegrator::Config& fractional = config->fractional;
  if (const auto entry = Find(table, prefix, kGain)) {
    fractional.gain = Bounded(*entry);
  }
  if (const auto entry = Find(table, prefix, kOrder)) {
    fractional.order = Bounded(*entry);
  }
  if (const auto entry = Find(table, prefix, kOustaloupN)) {
    fractional.oustaloup_n = Integer(*entry);
  }
  if (const auto entry = Find(table, prefix, kBand)) {
    const toml::array* band = entry->node->as_array();
    if (band == nullptr) FailType(*entry, "an array of two numbers [w_b, w_h]");
    if (band->size() != 2) {
      FailValue(*entry, entry->name + " must be an array of two numbers [w_b, w_h] (got " +
                            std::to_string(band->size()) + ")",
                "two numbers [w_b, w_h]");
    }
    double corners[2];
    for (int i = 0; i < 2; ++i) {
      Entry corner;
      corner.name = entry->name + "[" + std::to_string(i) + "]";
      corner.key = entry->key;
      corner.node = band->get(static_cast<std::size_t>(i));
      corner.line =
          corner.node->source().begin.line > 0 ? corner.node->source().begin.line : entry->line;
      corners[i] = Bounded(corner);
    }
    if (!(corners[0] < corners[1])) {
      FailValue(*entry, entry->name + " must have w_b < w_h (got [" + FormatShortest(corners[0]) +
                            ", " + FormatShortest(corners[1]) + "])",
                "w_b < w_h");
    }
    fractional.w_low_rad_s = corners[0];
    fractional.w_high_rad_s = corners[1];
  }

  const double sample_period_s = 1.0 / config->sample_rate_Hz;
  pid.sample_period_s = sample_period_s;
  pid.clamp_enabled = clamp;
  pid.v_max = v_max;
  fractional.sample_period_s = sample_period_s;
  fractional.clamp_enabled = clamp;
  fractional.v_max = v_max;
  try {
    if (config->controller == ControllerKind::kPid) {
      pid.Validate();
    } else {
      fractional.Validate();
    }
  } catch (const FieldError& error) {
    FailInTable(table, kController, ControllerKeyOfField(error.field()),
                std::string(kController) + ": " + error.what(), error.allowed());
  } catch (const std::invalid_argument& error) {
    FailInTable(table, kController, nullptr, std::string(kController) + ": " + error.what(), "");
  }
}

// [controller] realisation of the fractional integrator: "oustaloup"
// (K / s^lambda by Oustaloup, the default) or "eq15" (the paper's printed
// eq. 15, which fixes gain, order and band, so they are not settings).
void ScenarioReader::ReadRealisation(const toml::table& table,
                                     FractionalIntegrator::Config* fractional) const {
  const std::string prefix = std::string(kController) + ".";
  const auto entry = Find(table, prefix, kRealisation);
  if (!entry) return;
  const std::string word = Choice(*entry);
  fractional->realisation = *ParseFractionalRealisation(word);
  if (fractional->realisation == FractionalRealisation::kEq15) {
    RejectKeysOfOtherKind(table, prefix, {kGain, kOrder, kOustaloupN, kBand}, kOustaloup, word,
                          kRealisation);
  }
}

void ScenarioReader::ReadWaveform(const toml::table& table, WaveformConfig* wave) const {
  const std::string prefix = std::string(kWaveform) + ".";
  RejectUnknownKeys(table, prefix);

  std::string kind = kPolynomial;
  if (const auto entry = Find(table, prefix, kKind)) {
    kind = Choice(*entry);
  }
  wave->kind = kind == kPolynomial ? WaveformKind::kPolynomial : WaveformKind::kFractional;
  if (kind == kPolynomial) {
    RejectKeysOfOtherKind(table, prefix, {kC, kAlpha}, kFractional, kind);
  } else {
    RejectKeysOfOtherKind(table, prefix, {kC0, kC1, kC2}, kPolynomial, kind);
  }

  const std::pair<const char*, double*> numbers[] = {{kC0, &wave->c0_um},
                                                     {kC1, &wave->c1_um_per_mm},
                                                     {kC2, &wave->c2_um_per_mm2},
                                                     {kC, &wave->c_um},
                                                     {kAlpha, &wave->alpha},
                                                     {kFrequency, &wave->frequency_Hz},
                                                     {kWavelength, &wave->wavelength_mm}};
  for (const auto& [key, field] : numbers) {
    if (const auto entry = Find(table, prefix, key)) *field = Number(*entry);
  }

  try {
    wave->Validate();
  } catch (const FieldError& error) {
    // The field names of WaveformConfig are the keys of [waveform]; its
    // messages start "waveform: ".
    const char* key = nullptr;
    for (const char* name : {kC0, kC1, kC2, kC, kAlpha, kFrequency, kWavelength}) {
      if (error.field() == name) key = name;
    }
    FailInTable(table, kWaveform, key, error.what(), error.allowed());
  }
}

// 1 to kMaxLinks positive link lengths [mm].
void ScenarioReader::ReadLinkLengths(const Entry& entry, ScenarioConfig* config) const {
  const toml::array* lengths = entry.node->as_array();
  if (lengths == nullptr) FailType(entry, "an array of link lengths in mm");
  if (lengths->empty() || lengths->size() > static_cast<std::size_t>(kMaxLinks)) {
    FailValue(entry, entry.name + " must hold 1 to " + std::to_string(kMaxLinks) +
                         " lengths (got " + std::to_string(lengths->size()) + ")",
              "1 to " + std::to_string(kMaxLinks) + " lengths");
  }
  for (std::size_t i = 0; i < lengths->size(); ++i) {
    Entry length;
    length.name = entry.name + "[" + std::to_string(i) + "]";
    length.key = entry.key;
    length.node = lengths->get(i);
    length.line = length.node->source().begin.line > 0 ? length.node->source().begin.line
                                                       : entry.line;
    config->link_lengths_mm.push_back(Bounded(length));
  }
}

// The references' fade-in, in [0, cycles] wave periods.
void ScenarioReader::ReadStartRamp(const toml::table& table, ScenarioConfig* config) const {
  const auto entry = Find(table, std::string(kWaveform) + ".", kStartRamp);
  if (!entry) return;
  const double cycles = Number(*entry);
  if (cycles < 0.0 || cycles > config->cycles) {
    const std::string allowed = "in [0, cycles] = [0, " + std::to_string(config->cycles) + "]";
    FailValue(*entry, entry->name + " must be " + allowed + " (got " + FormatShortest(cycles) + ")",
              allowed);
  }
  config->start_ramp_cycles = cycles;
}

ScenarioConfig ScenarioReader::Read(const toml::table& root) const {
  RejectUnknownKeys(root, "");

  ScenarioConfig config;
  config.source = source_;

  if (const auto entry = Find(root, "", kLinkLengths)) ReadLinkLengths(*entry, &config);
  if (const auto entry = Find(root, "", kSegmentsPerLink)) {
    config.segments_per_link = Integer(*entry);
    // The generated flagellum (the generator's defaults but the links)
    // nests its bodies; MuJoCo's reader limits the nesting.
    const FlagellumSpec spec;
    const int links = config.link_lengths_mm.empty() ? spec.Links()
                                                     : static_cast<int>(config.link_lengths_mm.size());
    const int most = MaxSegmentsPerLink(links, spec.head_length_mm > 0);
    if (config.segments_per_link > most) {
      const std::string allowed = "[1, " + std::to_string(most) + "] for " +
                                  std::to_string(links) + " links and the head";
      FailValue(*entry,
                entry->name + " must be in " + allowed + " (got " +
                    std::to_string(config.segments_per_link) + "): MuJoCo 2.2 reads at most " +
                    std::to_string(kMaxNestedBodies) + " nested bodies",
                allowed);
    }
  }
  if (const auto entry = Find(root, "", kPlants)) {
    config.plants = *ParsePlantAssignment(Choice(*entry));
  }
  if (const auto entry = Find(root, "", kDynamics)) config.dynamics = ParseDynamics(Choice(*entry));
  const std::optional<Entry> model = Find(root, "", kModel);
  if (!model && !config.GeneratesModel()) {
    Fail(InputProblem::kMissing, 0, kModel,
         std::string(kModel) + " is required (or " + kLinkLengths + ")");
  }
  if (model) {
    namespace fs = std::filesystem;
    fs::path path(String(*model));
    if (path.is_relative()) path = fs::path(source_).parent_path() / path;
    path = fs::absolute(path).lexically_normal();
    std::error_code ignored;
    if (!fs::is_regular_file(path, ignored) || !std::ifstream(path).good()) {
      Fail(InputProblem::kUnreadable, model->line, model->key,
           std::string(kModel) + ": cannot open '" + path.string() + "'");
    }
    config.model_path = path.string();
  }

  if (const auto entry = Find(root, "", kActuation)) {
    config.actuation = Choice(*entry);
  }
  if (const auto entry = Find(root, "", kCycles)) config.cycles = Integer(*entry);
  if (const auto entry = Find(root, "", kTimestep)) {
    config.timestep_s = Bounded(*entry);
  }

  const toml::table* controller = Table(root, kController);
  if (controller != nullptr) {
    ReadController(*controller, &config);
  } else {
    config.pid.sample_period_s = 1.0 / config.sample_rate_Hz;
    config.fractional.sample_period_s = config.pid.sample_period_s;
  }
  // The controller is sampled every k physics steps, k a whole number.
  if (config.timestep_s) {
    const double steps_per_sample = 1.0 / (config.sample_rate_Hz * *config.timestep_s);
    const double whole = std::round(steps_per_sample);
    if (whole < 1.0 ||
        std::abs(steps_per_sample - whole) > kWholeStepsTolerance * steps_per_sample) {
      std::optional<Entry> where;
      if (controller != nullptr) {
        where = Find(*controller, std::string(kController) + ".", kSampleRate);
      }
      if (!where) where = Find(root, "", kTimestep);
      FailValue(*where, std::string(kController) + "." + kSampleRate +
                            " must make the sample period a whole number of timesteps (1 / (" +
                            FormatShortest(config.sample_rate_Hz) + " Hz x " +
                            FormatShortest(*config.timestep_s) +
                            " s) = " + FormatShortest(steps_per_sample) + ")",
                "a whole number of timesteps per sample");
    }
  }

  if (const toml::table* waveform = Table(root, kWaveform)) {
    ReadWaveform(*waveform, &config.waveform);
    ReadStartRamp(*waveform, &config);
  }

  if (const toml::table* fluid = Table(root, kFluid)) {
    const std::string prefix = std::string(kFluid) + ".";
    RejectUnknownKeys(*fluid, prefix);
    if (const auto entry = Find(*fluid, prefix, kViscosity)) config.viscosity_Pa_s = Bounded(*entry);
  }

  if (const toml::table* output = Table(root, kOutput)) {
    const std::string prefix = std::string(kOutput) + ".";
    RejectUnknownKeys(*output, prefix);
    if (const auto entry = Find(*output, prefix, kDir)) config.output_dir = String(*entry);
    if (const auto entry = Find(*output, prefix, kSamplesPerCycle)) {
      config.samples_per_cycle = Integer(*entry);
    }
  }
  return config;
}

// TOML values as ResolvedScenarioToml writes them.
std::string TomlString(const std::string& text) {
  std::ostringstream out;
  out << toml::value<std::string>(text);
  return out.str();
}
// The shortest text that reads back exactly, always a TOML float ("1000.0",
// "-0.0"), so that even the sign of zero survives.
std::string TomlFloat(double value) {
  std::string text = FormatShortest(value);
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  return text;
}
std::string TomlFloats(const std::vector<double>& values) {
  std::string text;
  for (double value : values) text += (text.empty() ? "" : ", ") + TomlFloat(value);
  return "[" + text + "]";
}
std::string TomlBool(bool value) { return value ? "true" : "false"; }

// Dotted key -> TOML value of every key a scenario resolves to.
std::map<std::string, std::string> ResolvedValues(const ScenarioConfig& config) {
  std::map<std::string, std::string> values;
  const auto set = [&](const std::string& key, std::string value) { values[key] = std::move(value); };
  if (!config.model_path.empty()) set(kModel, TomlString(config.model_path));
  if (!config.link_lengths_mm.empty()) set(kLinkLengths, TomlFloats(config.link_lengths_mm));
  if (config.segments_per_link > 0) set(kSegmentsPerLink, std::to_string(config.segments_per_link));
  if (config.plants) set(kPlants, TomlString(PlantAssignmentName(*config.plants)));
  set(kActuation, TomlString(config.actuation));
  if (config.dynamics) set(kDynamics, TomlString(DynamicsName(*config.dynamics)));
  set(kCycles, std::to_string(config.cycles));
  if (config.timestep_s) set(kTimestep, TomlFloat(*config.timestep_s));

  const std::string controller = std::string(kController) + ".";
  const bool pid = config.controller == ControllerKind::kPid;
  set(controller + kKind, TomlString(pid ? kPid : kFractional));
  set(controller + kSampleRate, TomlFloat(config.sample_rate_Hz));
  set(controller + kVMax, TomlFloat(pid ? config.pid.v_max : config.fractional.v_max));
  set(controller + kClamp,
      TomlBool(pid ? config.pid.clamp_enabled : config.fractional.clamp_enabled));
  if (pid) {
    set(controller + kKp, TomlFloat(config.pid.kp));
    set(controller + kKi, TomlFloat(config.pid.ki));
    set(controller + kKd, TomlFloat(config.pid.kd));
    set(controller + kDerivativeFilter, TomlFloat(config.pid.derivative_filter_time_s));
  } else {
    const FractionalIntegrator::Config& fractional = config.fractional;
    set(controller + kRealisation,
        TomlString(FractionalRealisationName(fractional.realisation)));
    if (fractional.realisation == FractionalRealisation::kOustaloup) {
      set(controller + kGain, TomlFloat(fractional.gain));
      set(controller + kOrder, TomlFloat(fractional.order));
      set(controller + kOustaloupN, std::to_string(fractional.oustaloup_n));
      set(controller + kBand, TomlFloats({fractional.w_low_rad_s, fractional.w_high_rad_s}));
    }
  }

  const std::string waveform = std::string(kWaveform) + ".";
  const WaveformConfig& wave = config.waveform;
  const bool polynomial = wave.kind == WaveformKind::kPolynomial;
  set(waveform + kKind, TomlString(polynomial ? kPolynomial : kFractional));
  if (polynomial) {
    set(waveform + kC0, TomlFloat(wave.c0_um));
    set(waveform + kC1, TomlFloat(wave.c1_um_per_mm));
    set(waveform + kC2, TomlFloat(wave.c2_um_per_mm2));
  } else {
    set(waveform + kC, TomlFloat(wave.c_um));
    set(waveform + kAlpha, TomlFloat(wave.alpha));
  }
  set(waveform + kFrequency, TomlFloat(wave.frequency_Hz));
  set(waveform + kWavelength, TomlFloat(wave.wavelength_mm));
  set(waveform + kStartRamp, TomlFloat(config.start_ramp_cycles));

  if (config.viscosity_Pa_s) {
    set(std::string(kFluid) + "." + kViscosity, TomlFloat(*config.viscosity_Pa_s));
  }
  set(std::string(kOutput) + "." + kSamplesPerCycle, std::to_string(config.samples_per_cycle));
  return values;
}

}  // namespace

std::string ResolvedScenarioToml(const ScenarioConfig& config) {
  std::map<std::string, std::string> values = ResolvedValues(config);
  // In the key table's order: the top-level keys, then one table after another.
  std::string text;
  std::string table;
  for (const KeySpec& key : ScenarioKeys()) {
    const auto value = values.find(key.name);
    if (value == values.end()) continue;
    const std::string name = key.name;
    const std::string::size_type dot = name.find('.');
    const std::string key_table = dot == std::string::npos ? "" : name.substr(0, dot);
    if (key_table != table) {
      text += "\n[" + key_table + "]\n";
      table = key_table;
    }
    text += name.substr(dot == std::string::npos ? 0 : dot + 1) + " = " + value->second + "\n";
    values.erase(value);
  }
  if (!values.empty()) {
    throw std::logic_error("scenario key " + values.begin()->first + " is not in the key table");
  }
  return text;
}

ScenarioConfig ParseScenario(const std::string& toml_text, const std::string& source) {
  const ScenarioReader reader(source);
  return reader.Read(ParseToml(toml_text, source));
}

ScenarioConfig LoadScenario(const std::string& path) {
  return ParseScenario(ReadTextFile(path, "scenario file"), path);
}

}  // namespace ipmc
