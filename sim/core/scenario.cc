// Scenario files: strict TOML reading. Every table is walked and checked
// against its list of keys; each key is read by its entry of the key table
// (sim/core/scenario_keys.cc), its value checked for type, finiteness and
// range before it reaches a Config, and the Configs' own Validate() runs
// last as a backstop (its FieldError is placed on the line of the key that
// set the field). Every error is an InputError, one line "FILE:LINE: key
// ...", built where it is found with its key and problem.
#include "sim/core/scenario.h"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sim/core/model_generator.h"
#include "sim/core/scenario_keys.h"
#include "sim/base/error.h"
#include "sim/io/files.h"
#include "sim/base/numbers.h"
#include "sim/io/toml.h"

namespace ipmc {
namespace {

// Relative tolerance on "a whole number of timesteps per controller sample".
constexpr double kWholeStepsTolerance = 1e-9;

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
  std::string file;  // the included file that wrote it; "" for the document's own source
};

// Reads one scenario document; every failure throws InputError
// (sim/base/error.h) naming the source, the line and the key, with one line
// of text.
class ScenarioReader {
 public:
  explicit ScenarioReader(std::string source) : source_(std::move(source)) {}

  // `key`: the dotted key (or table) the message is about.
  [[noreturn]] void Fail(InputProblem problem, std::uint32_t line, const std::string& key,
                         const std::string& message, const std::string& allowed = "") const {
    throw InputError(problem, {source_, line}, key, message, allowed);
  }
  // The same placed at `entry`, in the file that wrote it.
  [[noreturn]] void Fail(InputProblem problem, const Entry& entry, const std::string& message,
                         const std::string& allowed = "") const {
    throw InputError(problem, {entry.file.empty() ? source_ : entry.file, entry.line}, entry.key,
                     message, allowed);
  }
  // A bad value of `entry`, which must be `allowed`.
  [[noreturn]] void FailValue(const Entry& entry, const std::string& message,
                              const std::string& allowed) const {
    Fail(InputProblem::kBadValue, entry, message, allowed);
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
    // An included file's key keeps its own file (MergeTable).
    if (const auto& path = it->first.source().path; path && *path != source_) entry.file = *path;
    return entry;
  }

  [[noreturn]] void FailType(const Entry& entry, const std::string& expected) const {
    Fail(InputProblem::kWrongType, entry,
         entry.name + " must be " + expected + " (got " + TypeName(entry.node->type()) + ")",
         expected);
  }

  // An integer in the key's range (IntegerOutOfRange, sim/core/scenario_keys.h).
  int Integer(const Entry& entry) const {
    if (!entry.node->is_integer()) FailType(entry, "an integer");
    const std::int64_t value = entry.node->as_integer()->get();
    if (const auto error = IntegerOutOfRange(Spec(entry.key), entry.name, value)) {
      FailValue(entry, error->message, error->allowed);
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
      const std::string allowed = QuotedChoices(choices);
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

  // A finite number in the key's range (NumberOutOfRange); integers are
  // accepted.
  double Bounded(const Entry& entry) const {
    if (!entry.node->is_number()) FailType(entry, "a number");
    const double value = entry.node->is_integer()
                             ? static_cast<double>(entry.node->as_integer()->get())
                             : entry.node->as_floating_point()->get();
    if (const auto error = NumberOutOfRange(Spec(entry.key), entry.name, value)) {
      FailValue(entry, error->message, error->allowed);
    }
    return value;
  }

  // The value of dotted `key` in the document, if it is there.
  std::optional<Entry> FindKey(const toml::table& root, const std::string& key) const {
    const std::string::size_type dot = key.find('.');
    if (dot == std::string::npos) return Find(root, "", key.c_str());
    const std::string table_name = key.substr(0, dot);
    const toml::table* table = Table(root, table_name.c_str());
    if (table == nullptr) return std::nullopt;
    return Find(*table, table_name + ".", key.c_str() + dot + 1);
  }

  // Keys that belong to the other kind of a table are mistakes (a gain
  // that would be silently ignored), not settings: each of the key's
  // conditions must hold for the selectors read so far.
  void RequireConditions(const KeySpec& key, const Entry& entry,
                         const ScenarioConfig& config) const {
    const KeyCondition* condition = FailedCondition(key, config);
    if (condition == nullptr) return;
    const std::string selector = condition->selector;
    const std::string word = selector.substr(selector.find('.') + 1);
    Fail(InputProblem::kOtherKind, entry,
         entry.name + " applies only to " + word + " = " + Quoted(condition->value) + " (" + word +
             " is " + Quoted(SelectorValue(selector, config)) + ")");
  }

  // A Validate() failure of the Config behind table `table_name`, placed on
  // the line of the key that answers for the field.
  [[noreturn]] void FailValidation(const toml::table& root, const char* table_name,
                                   const std::string& field, const std::string& message,
                                   const std::string& allowed) const {
    const toml::table& table = *Table(root, table_name);
    const std::string prefix = std::string(table_name) + ".";
    for (const KeySpec& key : ScenarioKeys()) {
      const std::string name = key.name;
      if (name.rfind(prefix, 0) != 0 || !KeyHasField(key, field)) continue;
      if (const auto entry = Find(table, prefix, name.c_str() + prefix.size())) {
        FailValue(*entry, message, allowed);
      }
    }
    Fail(InputProblem::kBadValue, TableLine(table), table_name, message, allowed);
  }

  // fragment: an included file, which may leave the model to the file
  // that includes it.
  ScenarioConfig Read(const toml::table& root, bool fragment = false) const;

  const std::string& source() const { return source_; }

 private:
  void CheckWholeStepsPerSample(const toml::table& root, const ScenarioConfig& config) const;
  void CheckGeneratedModel(const toml::table& root, const ScenarioConfig& config) const;

  std::string source_;
};

// One value of the document as the key table's readers take it.
class DocumentValue : public KeyValue {
 public:
  DocumentValue(const ScenarioReader& reader, Entry entry)
      : reader_(reader), entry_(std::move(entry)) {}
  const std::string& name() const override { return entry_.name; }
  const std::string& source() const override { return reader_.source(); }
  double Number() const override { return reader_.Bounded(entry_); }
  int Integer() const override { return reader_.Integer(entry_); }
  bool Boolean() const override { return reader_.Boolean(entry_); }
  std::string String() const override { return reader_.String(entry_); }
  std::string Choice() const override { return reader_.Choice(entry_); }
  std::size_t ArraySize(const std::string& expected) const override {
    const toml::array* array = entry_.node->as_array();
    if (array == nullptr) reader_.FailType(entry_, expected);
    return array->size();
  }
  double NumberAt(std::size_t index) const override {
    Entry element;
    element.name = entry_.name + "[" + std::to_string(index) + "]";
    element.key = entry_.key;
    element.node = entry_.node->as_array()->get(index);
    element.line =
        element.node->source().begin.line > 0 ? element.node->source().begin.line : entry_.line;
    element.file = entry_.file;
    return reader_.Bounded(element);
  }
  [[noreturn]] void Fail(const std::string& message, const std::string& allowed,
                         InputProblem problem) const override {
    reader_.Fail(problem, entry_, message, allowed);
  }

 private:
  const ScenarioReader& reader_;
  Entry entry_;
};

// Every key of the table that the document holds, read in table order:
// first the selectors (the kinds of the tables), then, once every key's
// kind is checked, the others. The Configs' own Validate() runs last.
ScenarioConfig ScenarioReader::Read(const toml::table& root, bool fragment) const {
  RejectUnknownKeys(root, "");
  for (const std::string& name : ScenarioKeysUnder("")) {
    if (FindScenarioKey(name) != nullptr) continue;  // a key, not a table
    if (const toml::table* table = Table(root, name.c_str())) RejectUnknownKeys(*table, name + ".");
  }

  ScenarioConfig config;
  config.source = source_;
  std::vector<std::pair<const KeySpec*, Entry>> others;
  for (const KeySpec& key : ScenarioKeys()) {
    std::optional<Entry> entry = FindKey(root, key.name);
    if (!entry) continue;
    if (!IsKeySelector(key)) {
      others.emplace_back(&key, std::move(*entry));
      continue;
    }
    RequireConditions(key, *entry, config);
    key.read(DocumentValue(*this, *entry), config);
  }
  for (const auto& [key, entry] : others) RequireConditions(*key, entry, config);
  for (const auto& [key, entry] : others) key->read(DocumentValue(*this, entry), config);

  if (config.model.path.empty() && !config.model.Generated() && !fragment) {
    Fail(InputProblem::kMissing, 0, kModelKey,
         std::string(kModelKey) + " is required (or " + kLinkLengthsKey + ")");
  }

  config.controller.SetSamplePeriod();
  if (Table(root, kControllerTable) != nullptr) {
    try {
      config.controller.Validate();
    } catch (const FieldError& error) {
      FailValidation(root, kControllerTable, error.field(),
                     std::string(kControllerTable) + ": " + error.what(), error.allowed());
    } catch (const std::invalid_argument& error) {
      FailValidation(root, kControllerTable, "", std::string(kControllerTable) + ": " + error.what(),
                     "");
    }
  }
  CheckWholeStepsPerSample(root, config);
  if (config.model.Generated() && !fragment) CheckGeneratedModel(root, config);
  if (Table(root, kWaveformTable) != nullptr) {
    try {
      config.waveform.Validate();
    } catch (const FieldError& error) {
      // Its messages start "waveform: ".
      FailValidation(root, kWaveformTable, error.field(), error.what(), error.allowed());
    }
  }
  return config;
}

// The controller is sampled every k physics steps, k a whole number.
void ScenarioReader::CheckWholeStepsPerSample(const toml::table& root,
                                              const ScenarioConfig& config) const {
  if (!config.run.timestep_s) return;
  const double rate_Hz = config.controller.sample_rate_Hz;
  const double steps_per_sample = 1.0 / (rate_Hz * *config.run.timestep_s);
  const double whole = std::round(steps_per_sample);
  if (whole >= 1.0 &&
      std::abs(steps_per_sample - whole) <= kWholeStepsTolerance * steps_per_sample) {
    return;
  }
  const std::string ratio = "(1 / (" + FormatShortest(rate_Hz) + " Hz x " +
                            FormatShortest(*config.run.timestep_s) +
                            " s) = " + FormatShortest(steps_per_sample) + ")";
  // config.run.timestep_s is set: its key is in the document.
  const std::optional<Entry> rate = FindKey(root, kSampleRateKey);
  if (rate) {
    FailValue(*rate, std::string(kSampleRateKey) +
                         " must make the sample period a whole number of timesteps " + ratio,
              "a whole number of timesteps per sample");
  }
  // The rate is its default: the time step the user wrote is what to change.
  const double fitting_s = 1.0 / (rate_Hz * std::max(1.0, std::ceil(steps_per_sample)));
  FailValue(*FindKey(root, kTimestepKey),
            std::string(kTimestepKey) + " must make a controller sample (" + kSampleRateKey +
                " = " + FormatShortest(rate_Hz) + " Hz, its default) a whole number of timesteps " +
                ratio + ", e.g. " + kTimestepKey + " = " + FormatShortest(fitting_s),
            "1 / (sample rate x a whole number) s");
}

// The flagellum the scenario generates must be one the generator writes
// (a per-link array holds one value per link, ...); its FieldError is
// placed on the line of the key that set the field, else the first such
// key the document holds.
void ScenarioReader::CheckGeneratedModel(const toml::table& root,
                                         const ScenarioConfig& config) const {
  try {
    ScenarioFlagellumSpec(config.model).Validate();
  } catch (const FieldError& error) {
    std::optional<Entry> where;
    // Backwards: a per-link array before its scalar key.
    for (auto key = ScenarioKeys().rbegin(); key != ScenarioKeys().rend(); ++key) {
      if (!KeyHasField(*key, error.field())) continue;
      where = FindKey(root, key->name);
      if (where) break;
    }
    if (!where) where = FindKey(root, kLinkLengthsKey);
    const std::string message = error.what();
    const std::string reason = message.substr(message.find(": ") + 2);
    if (where) FailValue(*where, where->key + ": " + reason, error.allowed());
    Fail(InputProblem::kBadValue, 0, error.field(), reason, error.allowed());
  }
}

// Dotted key -> TOML value of every key a scenario resolves to: each key's
// writer, for the keys whose conditions the scenario meets.
std::map<std::string, std::string> ResolvedValues(const ScenarioConfig& config) {
  std::map<std::string, std::string> values;
  for (const KeySpec& key : ScenarioKeys()) {
    if (key.write == nullptr) continue;
    if (FailedCondition(key, config) != nullptr) continue;
    if (const std::optional<std::string> value = key.write(config)) values[key.name] = *value;
  }
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

namespace {

// Deepest chain of included files, and most files one scenario reads in
// all (a file included twice counts twice): a few small files that each
// include the next many times would otherwise read a number of files
// that grows as a power of the depth.
constexpr int kMaxIncludeDepth = 8;
constexpr int kMaxIncludedFiles = 64;

// The files being included, outermost first, and the count read so far.
struct IncludeChain {
  std::vector<std::string> files;
  int read = 0;
};

// `from`'s keys over `into`'s: tables merge key by key, any other value
// replaces the one before, and keeps its key's place (file and line) for
// the messages about it.
void MergeTable(toml::table& into, const toml::table& from) {
  for (auto&& [key, node] : from) {
    toml::table* inner = into.get_as<toml::table>(key.str());
    if (inner != nullptr && node.is_table()) {
      MergeTable(*inner, *node.as_table());
      continue;
    }
    into.erase(key.str());
    node.visit([&into, &key = key](auto&& value) { into.insert(key, value); });
  }
}

// The files `root`'s include key names, resolved against `source`'s folder.
std::vector<std::string> IncludedFiles(const toml::table& root, const std::string& source) {
  namespace fs = std::filesystem;
  const toml::node* node = root.get(kIncludeKey);
  if (node == nullptr) return {};
  const std::uint32_t line = node->source().begin.line;
  const std::string allowed = "a file or an array of files";
  std::vector<std::string> names;
  if (node->is_string()) names.push_back(node->as_string()->get());
  if (const toml::array* array = node->as_array()) {
    for (const toml::node& element : *array) {
      if (!element.is_string()) {
        throw InputError(InputProblem::kWrongType, {source, line}, kIncludeKey,
                         std::string(kIncludeKey) + " must be " + allowed + " (strings)", allowed);
      }
      names.push_back(element.as_string()->get());
    }
  }
  if (names.empty()) {
    throw InputError(InputProblem::kWrongType, {source, line}, kIncludeKey,
                     std::string(kIncludeKey) + " must be " + allowed + " (got " +
                         TomlTypeName(node->type()) + ")",
                     allowed);
  }
  std::vector<std::string> files;
  for (const std::string& name : names) {
    fs::path path(name);
    if (path.is_relative()) path = fs::path(source).parent_path() / path;
    files.push_back(fs::absolute(path).lexically_normal().string());
  }
  return files;
}

// The keys of `table` that generate the flagellum in place of a model
// file (ModelScenario::Generated): link_lengths_mm, segments_per_link and
// the [strip] and [plant] keys.
std::vector<std::string> GeneratingKeys(const toml::table& table) {
  std::vector<std::string> names = {kLinkLengthsKey, "segments_per_link"};
  for (const KeySpec& key : StripAndPlantKeys()) names.push_back(key.name);
  std::vector<std::string> found;
  for (const std::string& name : names) {
    if (table.at_path(name)) found.push_back(name);
  }
  return found;
}

// One file's keys as they reach a scenario: an included file's (with its
// own includes) or the scenario file's own.
struct KeySource {
  std::string file;
  const toml::table* table;
};

// The model and the keys that generate one both reach a scenario: the
// generated flagellum wins when its keys come from the same file as the
// model or from one over it (later in the include list, or the including
// file), which `notes` says in one line; a model given over generating
// keys (the including file's model over an included file's strip or
// plant) is refused, as the generator would ignore it.
void CompareModelWithGeneratingKeys(const std::vector<KeySource>& sources,
                                    const std::string& source, std::uint32_t include_line,
                                    std::vector<std::string>* notes) {
  int model_at = -1, generating_at = -1;
  for (int i = 0; i < static_cast<int>(sources.size()); ++i) {
    if (sources[i].table->contains(kModelKey)) model_at = i;
    if (!GeneratingKeys(*sources[i].table).empty()) generating_at = i;
  }
  if (model_at < 0 || generating_at < 0) return;
  const int own = static_cast<int>(sources.size()) - 1;  // the including file
  // An included file that holds both has said so when it was read.
  if (model_at == generating_at && model_at != own) return;
  const KeySource& model = sources[model_at];
  const KeySource& generating = sources[generating_at];
  std::string keys;
  for (const std::string& key : GeneratingKeys(*generating.table)) {
    keys += (keys.empty() ? "" : ", ") + key;
  }
  const std::string model_file = Quoted(model.table->get(kModelKey)->value_or(std::string()));
  if (model_at > generating_at) {
    const toml::node* node = model.table->get(kModelKey);
    const std::uint32_t line = model_at == own ? node->source().begin.line : include_line;
    throw InputError(InputProblem::kBadValue, {source, line}, kModelKey,
                     std::string(kModelKey) + " = " + model_file + " comes over " + keys +
                         " (in " + Quoted(generating.file) +
                         "), which generate a flagellum of their own with the generator's "
                         "defaults, not the model's: give one or the other",
                     "a model file, or keys that generate the flagellum, not both");
  }
  notes->push_back("the flagellum is generated from " + keys + " (" + Quoted(generating.file) +
                   ") in place of " + std::string(kModelKey) + " = " + model_file + " (" +
                   Quoted(model.file) + "): keys that generate a flagellum win over a model given "
                   "in the same file or before them");
}

// `root` with the keys of the files it includes under its own (each
// included file's own includes first), and its include key gone. Each
// included file is read as a scenario by itself first (but for the model,
// which the including file may give), so that its errors name it and its
// lines; its model path is made absolute, as relative to it.
toml::table WithIncludes(toml::table root, const std::string& source, IncludeChain* chain,
                         std::vector<std::string>* notes) {
  const std::vector<std::string> files = IncludedFiles(root, source);
  if (files.empty()) {
    CompareModelWithGeneratingKeys({{source, &root}}, source, 0, notes);
    return root;
  }
  const std::uint32_t line = root.get(kIncludeKey)->source().begin.line;
  if (chain->files.size() >= static_cast<std::size_t>(kMaxIncludeDepth)) {
    throw InputError(InputProblem::kBadValue, {source, line}, kIncludeKey,
                     std::string(kIncludeKey) + " nests deeper than " +
                         std::to_string(kMaxIncludeDepth) + " files",
                     "at most " + std::to_string(kMaxIncludeDepth) + " nested files");
  }
  toml::table merged;
  std::vector<toml::table> tables;  // each included file's, in order
  tables.reserve(files.size());
  for (const std::string& file : files) {
    if (std::find(chain->files.begin(), chain->files.end(), file) != chain->files.end()) {
      throw InputError(InputProblem::kBadValue, {source, line}, kIncludeKey,
                       std::string(kIncludeKey) + ": '" + file + "' includes itself",
                       "files that do not include each other");
    }
    if (++chain->read > kMaxIncludedFiles) {
      throw InputError(InputProblem::kBadValue, {source, line}, kIncludeKey,
                       std::string(kIncludeKey) + " reads more than " +
                           std::to_string(kMaxIncludedFiles) + " files in all",
                       "at most " + std::to_string(kMaxIncludedFiles) + " included files");
    }
    chain->files.push_back(file);
    toml::table included =
        WithIncludes(ParseToml(ReadTextFile(file, "included scenario file"), file), file, chain,
                     notes);
    chain->files.pop_back();
    if (const ScenarioConfig own = ScenarioReader(file).Read(included, /*fragment=*/true);
        !own.model.path.empty()) {
      included.insert_or_assign(kModelKey, own.model.path);
    }
    MergeTable(merged, included);
    tables.push_back(std::move(included));
  }
  root.erase(kIncludeKey);
  std::vector<KeySource> sources;
  for (std::size_t i = 0; i < files.size(); ++i) sources.push_back({files[i], &tables[i]});
  sources.push_back({source, &root});
  CompareModelWithGeneratingKeys(sources, source, line, notes);
  MergeTable(merged, root);
  return merged;
}

}  // namespace

ScenarioConfig ParseScenario(const std::string& toml_text, const std::string& source) {
  const ScenarioReader reader(source);
  IncludeChain chain;
  chain.files = {std::filesystem::absolute(source).lexically_normal().string()};
  std::vector<std::string> notes;
  ScenarioConfig config =
      reader.Read(WithIncludes(ParseToml(toml_text, source), source, &chain, &notes));
  config.notes = std::move(notes);
  return config;
}

ScenarioConfig LoadScenario(const std::string& path) {
  return ParseScenario(ReadTextFile(path, "scenario file"), path);
}

}  // namespace ipmc
