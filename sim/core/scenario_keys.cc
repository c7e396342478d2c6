#include "sim/core/scenario_keys.h"

#include <toml++/toml.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "controllers/controller_names.h"
#include "ipmc_swim/fields.h"
#include "sim/base/numbers.h"
#include "sim/core/controller_keys.h"
#include "sim/core/drive_keys.h"
#include "sim/core/fluid_keys.h"
#include "sim/core/key_builder.h"
#include "sim/core/model_generator.h"
#include "sim/core/scenario.h"
#include "sim/core/strip_keys.h"

namespace ipmc {

std::optional<std::string> TomlString(const std::string& text) {
  std::ostringstream out;
  out << toml::value<std::string>(text);
  return out.str();
}
std::string FloatText(double value) {
  std::string text = FormatShortest(value);
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  return text;
}
std::optional<std::string> TomlFloat(double value) { return FloatText(value); }
std::optional<std::string> TomlFloats(const std::vector<double>& values) {
  std::string text;
  for (double value : values) text += (text.empty() ? "" : ", ") + FloatText(value);
  return "[" + text + "]";
}
std::optional<std::string> TomlBool(bool value) { return value ? "true" : "false"; }
std::optional<std::string> TomlInteger(int value) { return std::to_string(value); }

std::string ReadablePath(const KeyValue& value, const std::string& what) {
  namespace fs = std::filesystem;
  fs::path path(value.String());
  if (path.empty()) {
    value.Fail(value.name() + ": an empty path; name " + what, "", InputProblem::kUnreadable);
  }
  if (path.is_relative()) path = fs::path(value.source()).parent_path() / path;
  path = fs::absolute(path).lexically_normal();
  std::error_code ignored;
  if (!fs::is_regular_file(path, ignored) || !std::ifstream(path).good()) {
    value.Fail(value.name() + ": cannot open '" + path.string() + "'", "",
               InputProblem::kUnreadable);
  }
  return path.string();
}

namespace {

// Selectors and the values they choose between.
constexpr char kWaveformKind[] = "waveform.kind";
// The waveform kind spelt as the controller kind.
constexpr const char* kFractional = controller_names::kFractional;
constexpr char kPolynomial[] = "polynomial";
constexpr int kMaxLinks = 20;

// The model, resolved against the scenario file's folder; it must be a
// readable file.
void ReadModel(const KeyValue& value, ScenarioConfig& config) {
  config.model.path = ReadablePath(value, "a model file (MJCF)");
}

// 1 to kMaxLinks positive link lengths [mm].
void ReadLinkLengths(const KeyValue& value, ScenarioConfig& config) {
  const std::size_t count = value.ArraySize("an array of link lengths in mm");
  const std::string allowed = "1 to " + std::to_string(kMaxLinks) + " lengths";
  if (count == 0 || count > static_cast<std::size_t>(kMaxLinks)) {
    value.Fail(value.name() + " must hold " + allowed + " (got " + std::to_string(count) + ")",
               allowed);
  }
  // A value replaces the lengths, as every reader sets its field.
  config.model.link_lengths_mm.clear();
  for (std::size_t i = 0; i < count; ++i) config.model.link_lengths_mm.push_back(value.NumberAt(i));
}

// The references' fade-in, in [0, cycles] wave periods (cycles is read
// before: it comes first in the table).
void ReadStartRamp(const KeyValue& value, ScenarioConfig& config) {
  const double cycles = value.Number();
  if (cycles < 0.0 || cycles > config.run.cycles) {
    const std::string allowed = "in [0, cycles] = [0, " + std::to_string(config.run.cycles) + "]";
    value.Fail(value.name() + " must be " + allowed + " (got " + FormatShortest(cycles) + ")",
               allowed);
  }
  config.waveform.start_ramp_cycles = cycles;
}

// A value of the IPMC impedance (sim/core/electrical.h), > 0; written when
// the electrical model is on or the value is not the default.
template <double ElectricalConfig::*kField>
KeySpec ElectricalKey(const char* name, const char* unit, const char* default_toml,
                      const char* example_toml, const char* meaning) {
  return Key(name, KeyType::kNumber, unit, "> 0", default_toml, meaning)
      .Default(default_toml)
      .Example(example_toml)
      .Refused("0")
      .Above(0.0)
      .Reads(
          [](const KeyValue& v, ScenarioConfig& c) { c.metrics.electrical.*kField = v.Number(); })
      .Writes([](const ScenarioConfig& c) {
        const bool shown = c.metrics.electrical.enabled ||
                           c.metrics.electrical.*kField != ElectricalConfig{}.*kField;
        return shown ? TomlFloat(c.metrics.electrical.*kField) : kLeftOut;
      });
}

// applies_when of every key: its conditions whose value is not the
// selector's default, as TOML lines.
void WriteAppliesWhen(std::vector<KeySpec>* keys) {
  for (KeySpec& key : *keys) {
    for (const KeyCondition& condition : key.only) {
      const auto selector = std::find_if(keys->begin(), keys->end(), [&](const KeySpec& k) {
        return std::string(k.name) == condition.selector;
      });
      const std::string value = "\"" + std::string(condition.value) + "\"";
      if (selector == keys->end() || value == selector->default_toml) continue;
      key.applies_when +=
          (key.applies_when.empty() ? "" : "\n") + std::string(condition.selector) + " = " + value;
    }
  }
}

// The model: its file, or the flagellum generated in its place, and its plants.
std::vector<KeySpec> ModelKeys() {
  using T = KeyType;
  return {
      // Read before the others (sim/core/scenario.cc, WithIncludes): the
      // document is its included files' keys with its own over them.
      Key(kIncludeKey, T::kString, "",
          "a TOML file of scenario keys, or an array of them; relative to this file; at most 8 "
          "deep and 64 files in all",
          "none",
          "Files of scenario keys read first, in order (each by itself, its model relative to "
          "it), under this file's own keys: e.g. the plant.toml `identify` writes")
          .Example("\"paper.toml\"")
          .Reads([](const KeyValue&, ScenarioConfig&) {}),
      Key(kModelKey, T::kString, "", "a readable MJCF file; relative to the scenario file's folder",
          "none: required unless link_lengths_mm or segments_per_link",
          "The MJCF model: links, IPMC actuators and RFT drag (its `ipmc_*` fields)")
          .Example("\"../models/flagellum3.xml\"")
          .Refused("\"no_such_model.xml\"")
          .Reads(ReadModel)
          .Writes([](const ScenarioConfig& c) {
            return c.model.path.empty() ? kLeftOut : TomlString(c.model.path);
          }),
      Key(kLinkLengthsKey, T::kNumberArray, "mm", "1 to 20 lengths, each > 0",
          "none: the model file",
          "Generate the flagellum with these links (the generator's other defaults) "
          "instead of reading model; wins over model")
          .Example("[8, 10, 12]")
          .Refused("[10, -1]")
          .Above(0.0)
          .Reads(ReadLinkLengths)
          .Writes([](const ScenarioConfig& c) {
            return c.model.link_lengths_mm.empty() ? kLeftOut : TomlFloats(c.model.link_lengths_mm);
          }),
      Key("segments_per_link", T::kInteger, "",
          "[1, 64] and 1 + links x segments_per_link <= 96 (31 on three links): MuJoCo 2.2 "
          "nests at most 96 bodies, the head included",
          "none: the model file",
          "Rigid sub-segments per link; also generates the flagellum (links of 10 mm "
          "unless link_lengths_mm)")
          .Example("2")
          .Refused("65")
          .AtLeast(1)
          .AtMost(kMaxSegmentsPerLink)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.model.segments_per_link = v.Integer();
            // The generated flagellum (the generator's defaults but the
            // links) nests its bodies; MuJoCo's reader limits the nesting.
            // link_lengths_mm, read before this key, gives the links.
            const FlagellumSpec spec;
            const int links = c.model.link_lengths_mm.empty()
                                  ? spec.Links()
                                  : static_cast<int>(c.model.link_lengths_mm.size());
            const int most = MaxSegmentsPerLink(links, spec.head_length_mm > 0);
            if (c.model.segments_per_link > most) {
              const std::string allowed = "[1, " + std::to_string(most) + "] for " +
                                          std::to_string(links) + " links and the head";
              v.Fail(v.name() + " must be in " + allowed + " (got " +
                         std::to_string(c.model.segments_per_link) +
                         "): MuJoCo 2.2 reads at most " + std::to_string(kMaxNestedBodies) +
                         " nested bodies",
                     allowed);
            }
          })
          .Writes([](const ScenarioConfig& c) {
            return c.model.segments_per_link > 0 ? TomlInteger(c.model.segments_per_link)
                                                 : kLeftOut;
          }),
      Key("plants", T::kChoice, "", "\"uniform\" or \"table2\"", "the model's `ipmc_plants`",
          "uniform: every link eq. 7's plant; table2: link q Table 2's row q")
          .Example("\"table2\"")
          .Refused("\"measured\"")
          .Choices("uniform|table2")
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.model.plants = *ParsePlantAssignment(v.Choice());
          })
          .Writes([](const ScenarioConfig& c) {
            return c.model.plants ? TomlString(PlantAssignmentName(*c.model.plants)) : kLeftOut;
          }),
  };
}

// How the run drives and steps the model, and for how long.
std::vector<KeySpec> RunKeys() {
  using T = KeyType;
  return {
      Key("actuation", T::kChoice, "", "", "\"distributed\"",
          "distributed: one controller and voltage per link; single: only link 1 is driven")
          .Default("\"distributed\"")
          .Example("\"single\"")
          .Refused("\"none\"")
          .Choices(kActuationNames)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.actuation = ChoiceValue(kActuationNames, v.Choice());
          })
          .Writes([](const ScenarioConfig& c) {
            return TomlString(ChoiceText(kActuationNames, c.actuation));
          }),
      Key("dynamics", T::kChoice, "", "\"inertial\" or \"stokes\"",
          "the model's `ipmc_dynamics` (inertial if absent)",
          "inertial: mj_step with the bodies' inertia; stokes: no inertia, velocities from the "
          "force balance, implicit in the hinge stiffness (docs/DYNAMICS.md)")
          .Example("\"stokes\"")
          .Refused("\"quasi_static\"")
          .Choices("inertial|stokes")
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.model.dynamics = ParseDynamics(v.Choice());
          })
          .Writes([](const ScenarioConfig& c) {
            return c.model.dynamics ? TomlString(DynamicsName(*c.model.dynamics)) : kLeftOut;
          }),
      Key("hinge_damping_scale", T::kNumber, "", ">= 0", "1",
          "Multiplies the damping of every joint of the model (the hinges' `damping`, not the "
          "paper's plant: docs/ENERGY.md); the inertial step takes each hinge's c as "
          "c_eff = k h / (1 - exp(-k h / c)), stable for every scale; a run's model.xml "
          "says the scale it holds (scenario_hinge_damping_scale), against which the "
          "scale is taken")
          .Default("1.0")
          .Example("0.5")
          .Refused("-1")
          .AtLeast(0.0)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.model.hinge_damping_scale = v.Number();
          })
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.model.hinge_damping_scale); }),
      Key("cycles", T::kInteger, "", ">= 1", "3", "Wave periods to run")
          .Default("3")
          .Refused("0")
          .AtLeast(1)
          .AtMost(INT_MAX)
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.run.cycles = v.Integer(); })
          .Writes([](const ScenarioConfig& c) { return TomlInteger(c.run.cycles); }),
      Key(kTimestepKey, T::kNumber, "s", "(0, 1e-3]; a whole number of steps per controller sample",
          "the model's timestep", "Physics time step, overriding the model's")
          .Example("5e-4")
          .Refused("2e-3")
          .Above(0.0)
          .AtMost(1e-3)
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.run.timestep_s = v.Number(); })
          .Writes([](const ScenarioConfig& c) {
            return c.run.timestep_s ? TomlFloat(*c.run.timestep_s) : kLeftOut;
          }),
  };
}

// [waveform]: the travelling wave the links track (eq. 2, 3).
std::vector<KeySpec> WaveformKeys() {
  using T = KeyType;
  return {
      Key(kWaveformKind, T::kChoice, "", "", "\"polynomial\"",
          "polynomial: eq. 2 with Table 4's envelope; fractional: the envelope c x^alpha (eq. 3)")
          .Default("\"polynomial\"")
          .Example("\"fractional\"")
          .Refused("\"sine\"")
          .Choices(kWaveformKindNames)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.waveform.kind = ChoiceValue(kWaveformKindNames, v.Choice());
          })
          .Writes([](const ScenarioConfig& c) {
            return TomlString(ChoiceText(kWaveformKindNames, c.waveform.kind));
          }),
      Key("waveform.c0_um", T::kNumber, "um", "finite", "0", "Polynomial: envelope c0")
          .Default("0.0")
          .Example("10.0")
          .Only(kWaveformKind, kPolynomial)
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.waveform.c0_um = v.Number(); })
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.waveform.c0_um); }),
      Key("waveform.c1_um_per_mm", T::kNumber, "um/mm", "finite", "200",
          "Polynomial: envelope c1 (x in mm from the head)")
          .Default("200.0")
          .Example("100.0")
          .Only(kWaveformKind, kPolynomial)
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.waveform.c1_um_per_mm = v.Number(); })
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.waveform.c1_um_per_mm); }),
      Key("waveform.c2_um_per_mm2", T::kNumber, "um/mm^2", "finite", "0", "Polynomial: envelope c2")
          .Default("0.0")
          .Example("1.0")
          .Only(kWaveformKind, kPolynomial)
          .Reads(
              [](const KeyValue& v, ScenarioConfig& c) { c.waveform.c2_um_per_mm2 = v.Number(); })
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.waveform.c2_um_per_mm2); }),
      Key("waveform.c_um", T::kNumber, "um/mm^alpha", "finite", "0", "Fractional: envelope c")
          .Default("0.0")
          .Example("300.0")
          .Only(kWaveformKind, kFractional)
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.waveform.c_um = v.Number(); })
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.waveform.c_um); }),
      Key("waveform.alpha", T::kNumber, "", "(0, 1]", "0.5", "Fractional: envelope exponent alpha")
          .Default("0.5")
          .Refused("0")
          .Only(kWaveformKind, kFractional)
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.waveform.alpha = v.Number(); })
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.waveform.alpha); }),
      Key("waveform.frequency_Hz", T::kNumber, "Hz", "finite and != 0", "0.01",
          "Wave frequency f; < 0 sends the wave tail-to-head")
          .Default("0.01")
          .Refused("0")
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.waveform.frequency_Hz = v.Number(); })
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.waveform.frequency_Hz); }),
      Key("waveform.wavelength_mm", T::kNumber, "mm", "finite and > 0", "32", "Wavelength lambda")
          .Default("32.0")
          .Refused("0")
          .Reads(
              [](const KeyValue& v, ScenarioConfig& c) { c.waveform.wavelength_mm = v.Number(); })
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.waveform.wavelength_mm); }),
      Key("waveform.start_ramp_cycles", T::kNumber, "", "[0, cycles]", "0.25",
          "The references (and a sine drive's voltages) fade in by (1 - cos(pi t / T_r)) / 2 over "
          "T_r = this / f")
          .Default("0.25")
          .Refused("-1")
          .Reads(ReadStartRamp)
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.waveform.start_ramp_cycles); }),
  };
}

// [metrics]: the cycles the run's summary metrics cover.
std::vector<KeySpec> MetricsKeys() {
  using T = KeyType;
  return {
      Key("metrics.from_cycle", T::kInteger, "", "[1, cycles]",
          "the first cycle after the start ramp (the last cycle if none is)",
          "The first cycle of the links' IAE, ITAE, RMS and peak voltage and clamped fraction, the "
          "mean speed and the mean powers (1: the whole run, start-up included); per-cycle "
          "tables keep every cycle")
          .Example("2")
          .Refused("0")
          .AtLeast(1)
          .AtMost(INT_MAX)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            const int first = v.Integer();
            if (first > c.run.cycles) {
              const std::string allowed =
                  "in [1, cycles] = [1, " + std::to_string(c.run.cycles) + "]";
              v.Fail(v.name() + " must be " + allowed + " (got " + std::to_string(first) + ")",
                     allowed);
            }
            c.metrics.from_cycle = first;
          })
          .Writes([](const ScenarioConfig& c) {
            return c.metrics.from_cycle > 0 ? TomlInteger(c.metrics.from_cycle) : kLeftOut;
          }),
  };
}

// [electrical]: the IPMC impedance behind each link's electrical power.
std::vector<KeySpec> ElectricalKeys() {
  using T = KeyType;
  return {
      Key("electrical.enabled", T::kBoolean, "", "true or false", "false",
          "Each link's electrical power <V I> and the electromechanical efficiency from the IPMC "
          "impedance R_s + (R_p || C) per unit electrode area, scaled by the link's length x "
          "electrical.electrode_width_mm (sim/core/electrical.h; docs/ENERGY.md: representative "
          "values, not a measured set)")
          .Default("false")
          .Example("true")
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.metrics.electrical.enabled = v.Boolean();
          })
          .Writes([](const ScenarioConfig& c) {
            return c.metrics.electrical.enabled ? TomlBool(true) : kLeftOut;
          }),
      ElectricalKey<&ElectricalConfig::series_resistance_ohm_m2>(
          "electrical.series_resistance_ohm_m2", "ohm m^2", "1.0e-4", "2e-4",
          "Series (electrode and contact) resistance r_s times the electrode area: R_s = r_s / A"),
      ElectricalKey<&ElectricalConfig::parallel_resistance_ohm_m2>(
          "electrical.parallel_resistance_ohm_m2", "ohm m^2", "1.0e-2", "5e-3",
          "Leakage resistance r_p across the double layer times the electrode area: R_p = r_p / A"),
      ElectricalKey<&ElectricalConfig::capacitance_F_m2>(
          "electrical.capacitance_F_m2", "F/m^2", "10.0", "20.0",
          "Double-layer capacitance per unit electrode area: C = c A"),
      ElectricalKey<&ElectricalConfig::electrode_width_mm>(
          "electrical.electrode_width_mm", "mm", "3.0", "2.5",
          "Electrode width; a link's electrode area A is its length times this"),
  };
}

// [output]: what the run writes.
std::vector<KeySpec> OutputKeys() {
  using T = KeyType;
  return {
      Key("output.dir", T::kString, "", "a directory; relative to the working directory",
          "\"\": no files", "Where timeseries.csv, states.csv, model.xml and summary.json go")
          .Default("\"\"")
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.output.dir = v.String(); }),
      Key("output.samples_per_cycle", T::kInteger, "", ">= 1", "200",
          "Time-series samples per wave period")
          .Default("200")
          .Refused("0")
          .AtLeast(1)
          .AtMost(INT_MAX)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.output.samples_per_cycle = v.Integer();
          })
          .Writes([](const ScenarioConfig& c) { return TomlInteger(c.output.samples_per_cycle); }),
  };
}

// Every scenario key, one part after another in the order the reader lists
// them: the top-level keys, the strip and its plants (the robot), then
// one table after another.
std::vector<KeySpec> MakeScenarioKeys() {
  static_assert(kMaxSegmentsPerLink == 64, "the allowed ranges state this limit");
  std::vector<KeySpec> keys;
  for (std::vector<KeySpec> (*part)() :
       {ModelKeys, RunKeys, StripAndPlantKeys, ControllerKeys, WaveformKeys, DriveKeys, FluidKeys,
        MetricsKeys, ElectricalKeys, OutputKeys}) {
    const std::vector<KeySpec> part_keys = part();
    keys.insert(keys.end(), part_keys.begin(), part_keys.end());
  }
  WriteAppliesWhen(&keys);
  return keys;
}

std::vector<KeySpec> MakeSweepFileKeys() {
  using T = KeyType;
  return {
      Key("base", T::kString, "", "a scenario file; relative to the sweep file's folder",
          "none: required (but with gait)", "The scenario every point starts from"),
      Key("gait", T::kTable, "",
          "the options of ipmc-swim gait but out (model, gait, frequency_Hz, amplitude_rad, "
          "phase_lag_rad, amplitudes_rad, phases_rad, csv, cycles, samples_per_cycle, "
          "allow_long); paths relative to the sweep file; not with base",
          "none",
          "Every point runs this prescribed gait instead of a closed-loop scenario; set, grid "
          "and point then hold gait options, and the table the gait's metrics"),
      Key("set", T::kTable, "", "scenario keys (dotted, or as nested tables)", "none",
          "Overrides applied to every point (not columns of the table)"),
      Key("grid", T::kTable, "", "scenario keys, each an array of values; not with point", "none",
          "The Cartesian product of the arrays, the first key outermost"),
      Key("point", T::kTableArray, "", "tables of scenario keys; not with grid", "none",
          "One point per [[point]] table, in file order"),
      Key("keep_runs", T::kBoolean, "", "true or false", "false",
          "Keep each point's run directory (timeseries.csv, states.csv, summary.json) in "
          "PREFIX_runs/point_N, as sweep --keep-runs does"),
  };
}

}  // namespace

const std::vector<KeySpec>& ScenarioKeys() {
  static const std::vector<KeySpec> keys = MakeScenarioKeys();
  return keys;
}

const std::vector<KeySpec>& SweepFileKeys() {
  static const std::vector<KeySpec> keys = MakeSweepFileKeys();
  return keys;
}

const KeySpec* FindScenarioKey(std::string_view name) {
  for (const KeySpec& key : ScenarioKeys()) {
    if (name == key.name) return &key;
  }
  return nullptr;
}

std::vector<std::string> ScenarioKeysUnder(std::string_view table) {
  std::vector<std::string> names;
  const std::string prefix = table.empty() ? "" : std::string(table) + ".";
  for (const KeySpec& key : ScenarioKeys()) {
    const std::string name = key.name;
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = name.substr(prefix.size());
    const std::string first = rest.substr(0, rest.find('.'));
    bool seen = false;
    for (const std::string& known : names) seen = seen || known == first;
    if (!seen) names.push_back(first);
  }
  return names;
}

bool KeyHasField(const KeySpec& key, const std::string& field) {
  std::string fields = key.fields;
  if (fields.empty()) {
    const std::string name = key.name;
    fields = name.substr(name.rfind('.') + 1);
  }
  std::istringstream words(fields);
  std::string word;
  while (words >> word) {
    if (word == field) return true;
  }
  return false;
}

bool IsKeySelector(const KeySpec& key) {
  for (const KeySpec& other : ScenarioKeys()) {
    for (const KeyCondition& condition : other.only) {
      if (std::string(condition.selector) == key.name) return true;
    }
  }
  return false;
}

std::string SelectorValue(const std::string& selector, const ScenarioConfig& config) {
  const KeySpec* key = FindScenarioKey(selector);
  if (key == nullptr || key->type != KeyType::kChoice || key->write == nullptr) {
    throw std::logic_error("scenario key " + selector + " is not a selector");
  }
  // A choice is written as a TOML string of plain characters: 'pid'; a
  // selector left out of a resolved scenario has its default ("" if it has
  // none: the model file decides, fluid.model).
  const std::string text = key->write(config).value_or(key->default_toml);
  return text.size() < 2 ? "" : text.substr(1, text.size() - 2);
}

const KeyCondition* FailedCondition(const KeySpec& key, const ScenarioConfig& config) {
  for (const KeyCondition& condition : key.only) {
    if (SelectorValue(condition.selector, config) != condition.value) return &condition;
  }
  return nullptr;
}

std::vector<std::string> KeyChoices(const KeySpec& key) {
  std::vector<std::string> choices;
  const std::string text = key.choices;
  std::size_t start = 0;
  while (start <= text.size() && !text.empty()) {
    const std::size_t bar = text.find('|', start);
    choices.push_back(text.substr(start, bar == std::string::npos ? bar : bar - start));
    if (bar == std::string::npos) break;
    start = bar + 1;
  }
  return choices;
}

namespace {

// "NAME must be RELATION BOUND (got VALUE)", the bound and the value
// written by `text`.
template <typename Value, typename Text>
std::optional<KeyRangeError> OutOfRange(const KeySpec& key, const std::string& name, Value value,
                                        Value minimum, Value maximum, const Text& text) {
  const auto error = [&](const char* relation, Value bound) {
    const std::string allowed = relation + text(bound);
    return KeyRangeError{name + " must be " + allowed + " (got " + text(value) + ")", allowed};
  };
  if (key.lower == Bound::kClosed && !(value >= minimum)) return error(">= ", minimum);
  if (key.lower == Bound::kOpen && !(value > minimum)) return error("> ", minimum);
  if (key.upper == Bound::kClosed && !(value <= maximum)) return error("<= ", maximum);
  if (key.upper == Bound::kOpen && !(value < maximum)) return error("< ", maximum);
  return std::nullopt;
}

}  // namespace

std::optional<KeyRangeError> NumberOutOfRange(const KeySpec& key, const std::string& name,
                                              double value) {
  if (!std::isfinite(value)) {
    return KeyRangeError{name + " must be finite (got " + FormatShortest(value) + ")", "finite"};
  }
  return OutOfRange(key, name, value, key.minimum, key.maximum,
                    [](double number) { return FormatShortest(number); });
}

std::optional<KeyRangeError> IntegerOutOfRange(const KeySpec& key, const std::string& name,
                                               long long value) {
  return OutOfRange(key, name, value, static_cast<long long>(key.minimum),
                    static_cast<long long>(key.maximum),
                    [](long long number) { return std::to_string(number); });
}

std::string QuotedChoices(const std::vector<std::string>& choices) {
  std::string text;
  for (const std::string& choice : choices) {
    text += (text.empty() ? "\"" : " or \"") + choice + "\"";
  }
  return text;
}

std::string KeyTypeName(KeyType type) {
  switch (type) {
    case KeyType::kString:
      return "string";
    case KeyType::kChoice:
      return "choice";
    case KeyType::kBoolean:
      return "boolean";
    case KeyType::kInteger:
      return "integer";
    case KeyType::kNumber:
      return "number";
    case KeyType::kNumberArray:
      return "array of numbers";
    case KeyType::kTable:
      return "table";
    case KeyType::kTableArray:
      return "array of tables";
  }
  return "?";
}

}  // namespace ipmc
