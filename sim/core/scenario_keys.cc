#include "sim/core/scenario_keys.h"

#include <climits>
#include <cstddef>
#include <string>

#include "controllers/fractional_integrator.h"
#include "plugin/actuators/ipmc_actuators.h"

namespace ipmc {
namespace {

// Builds one KeySpec entry by named steps.
class Key {
 public:
  Key(const char* name, KeyType type, const char* unit, const char* allowed,
      const char* default_text, const char* meaning) {
    spec_.name = name;
    spec_.type = type;
    spec_.unit = unit;
    spec_.allowed = allowed;
    spec_.default_text = default_text;
    spec_.meaning = meaning;
  }
  Key& Default(const char* toml) { spec_.default_toml = toml; return *this; }
  Key& Example(const char* toml) { spec_.example_toml = toml; return *this; }
  Key& Refused(const char* toml) { spec_.refused_toml = toml; return *this; }
  Key& When(const char* toml_lines) { spec_.applies_when = toml_lines; return *this; }
  Key& Choices(const char* choices) { spec_.choices = choices; return *this; }
  Key& Above(double minimum) { return Lower(Bound::kOpen, minimum); }
  Key& AtLeast(double minimum) { return Lower(Bound::kClosed, minimum); }
  Key& AtMost(double maximum) {
    spec_.upper = Bound::kClosed;
    spec_.maximum = maximum;
    return *this;
  }
  operator KeySpec() const { return spec_; }

 private:
  Key& Lower(Bound bound, double minimum) {
    spec_.lower = bound;
    spec_.minimum = minimum;
    return *this;
  }
  KeySpec spec_{};
};

constexpr char kFractional[] = "controller.kind = \"fractional\"";
constexpr char kFractionalWave[] = "waveform.kind = \"fractional\"";

std::vector<KeySpec> MakeScenarioKeys() {
  using T = KeyType;
  static_assert(kMaxSegmentsPerLink == 64 && kMaxOustaloupPairs == 64,
                "the allowed ranges below state these limits");
  return {
      Key("model", T::kString, "", "a readable MJCF file; relative to the scenario file's folder",
          "none: required unless link_lengths_mm or segments_per_link",
          "The MJCF model: links, IPMC actuators and RFT drag (its `ipmc_*` fields)")
          .Example("\"../models/flagellum3.xml\"")
          .Refused("\"no_such_model.xml\""),
      Key("link_lengths_mm", T::kNumberArray, "mm", "1 to 20 lengths, each > 0",
          "none: the model file",
          "Generate the flagellum with these links (the generator's other defaults) "
          "instead of reading model; wins over model")
          .Example("[8, 10, 12]")
          .Refused("[10, -1]")
          .Above(0.0),
      Key("segments_per_link", T::kInteger, "",
          "[1, 64] and 1 + links x segments_per_link <= 96 (31 on three links): MuJoCo 2.2 "
          "nests at most 96 bodies, the head included", "none: the model file",
          "Rigid sub-segments per link; also generates the flagellum (links of 10 mm "
          "unless link_lengths_mm)")
          .Example("2")
          .Refused("65")
          .AtLeast(1)
          .AtMost(kMaxSegmentsPerLink),
      Key("plants", T::kChoice, "", "\"uniform\" or \"table2\"", "the model's `ipmc_plants`",
          "uniform: every link eq. 7's plant; table2: link q Table 2's row q")
          .Example("\"table2\"")
          .Refused("\"measured\"")
          .Choices("uniform|table2"),
      Key("actuation", T::kChoice, "", "\"distributed\" or \"single\"", "\"distributed\"",
          "distributed: one controller and voltage per link; single: only link 1 is driven")
          .Default("\"distributed\"")
          .Example("\"single\"")
          .Refused("\"none\"")
          .Choices("distributed|single"),
      Key("dynamics", T::kChoice, "", "\"inertial\" or \"stokes\"",
          "the model's `ipmc_dynamics` (inertial if absent)",
          "inertial: mj_step with the bodies' inertia; stokes: no inertia, velocities from the "
          "force balance, implicit in the hinge stiffness (docs/DYNAMICS.md)")
          .Example("\"stokes\"")
          .Refused("\"quasi_static\"")
          .Choices("inertial|stokes"),
      Key("cycles", T::kInteger, "", ">= 1", "3", "Wave periods to run")
          .Default("3")
          .Refused("0")
          .AtLeast(1)
          .AtMost(INT_MAX),
      Key("timestep_s", T::kNumber, "s",
          "(0, 1e-3]; a whole number of steps per controller sample", "the model's timestep",
          "Physics time step, overriding the model's")
          .Example("5e-4")
          .Refused("2e-3")
          .Above(0.0)
          .AtMost(1e-3),
      Key("controller.kind", T::kChoice, "", "\"pid\" or \"fractional\"", "\"pid\"",
          "pid: eq. 12 per link; fractional: K / s^lambda per link (eq. 13-15)")
          .Default("\"pid\"")
          .Example("\"fractional\"")
          .Refused("\"lqr\"")
          .Choices("pid|fractional"),
      Key("controller.sample_rate_Hz", T::kNumber, "Hz",
          "> 0; a whole number of time steps per sample", "1000",
          "Controller sample rate (the data-acquisition board's)")
          .Default("1000.0")
          .Refused("0")
          .Above(0.0),
      Key("controller.v_max_V", T::kNumber, "V", "> 0", "6", "Output voltage limit")
          .Default("6.0")
          .Refused("0")
          .Above(0.0),
      Key("controller.clamp", T::kBoolean, "", "true or false", "true",
          "Clamp the output to +-v_max_V with anti-windup; false: the linear loop")
          .Default("true")
          .Example("false"),
      Key("controller.kp", T::kNumber, "V/mm", ">= 0", "8.12", "PID: proportional gain Kp")
          .Default("8.12")
          .Refused("-1")
          .AtLeast(0.0),
      Key("controller.ki", T::kNumber, "V/(mm s)", ">= 0", "53.36", "PID: integral gain Ki")
          .Default("53.36")
          .Refused("-1")
          .AtLeast(0.0),
      Key("controller.kd", T::kNumber, "V s/mm", ">= 0", "0.61", "PID: derivative gain Kd")
          .Default("0.61")
          .Refused("-1")
          .AtLeast(0.0),
      Key("controller.derivative_filter_s", T::kNumber, "s", ">= 0", "0",
          "PID: derivative filter time constant Tf (0: the ideal derivative)")
          .Default("0.0")
          .Example("0.01")
          .Refused("-1")
          .AtLeast(0.0),
      Key("controller.gain", T::kNumber, "V/(mm s^lambda)", ">= 0", "15.62",
          "Fractional: gain K")
          .Default("15.62")
          .Refused("-1")
          .When(kFractional)
          .AtLeast(0.0),
      Key("controller.order", T::kNumber, "", "(0, 1]", "0.62", "Fractional: order lambda")
          .Default("0.62")
          .Refused("1.5")
          .When(kFractional)
          .Above(0.0)
          .AtMost(1.0),
      Key("controller.oustaloup_n", T::kInteger, "", "[1, 64]", "4",
          "Fractional: Oustaloup pole-zero pairs N")
          .Default("4")
          .Refused("0")
          .When(kFractional)
          .AtLeast(1)
          .AtMost(kMaxOustaloupPairs),
      Key("controller.band_rad_s", T::kNumberArray, "rad/s", "two numbers [w_b, w_h], 0 < w_b < w_h",
          "[1e-3, 1e2]", "Fractional: Oustaloup's fitting band")
          .Default("[1e-3, 1e2]")
          .Refused("[10, 1]")
          .When(kFractional)
          .Above(0.0),
      Key("controller.realisation", T::kChoice, "", "\"oustaloup\" or \"eq15\"", "\"oustaloup\"",
          "Fractional: oustaloup (K / s^lambda on the band) or eq15 (the paper's printed eq. "
          "15; no gain, order, oustaloup_n or band_rad_s)")
          .Default("\"oustaloup\"")
          .Example("\"eq15\"")
          .Refused("\"tustin\"")
          .When(kFractional)
          .Choices("oustaloup|eq15"),
      Key("waveform.kind", T::kChoice, "", "\"polynomial\" or \"fractional\"", "\"polynomial\"",
          "polynomial: eq. 2 with Table 4's envelope; fractional: the envelope c x^alpha (eq. 3)")
          .Default("\"polynomial\"")
          .Example("\"fractional\"")
          .Refused("\"sine\"")
          .Choices("polynomial|fractional"),
      Key("waveform.c0_um", T::kNumber, "um", "finite", "0", "Polynomial: envelope c0")
          .Default("0.0")
          .Example("10.0"),
      Key("waveform.c1_um_per_mm", T::kNumber, "um/mm", "finite", "200",
          "Polynomial: envelope c1 (x in mm from the head)")
          .Default("200.0")
          .Example("100.0"),
      Key("waveform.c2_um_per_mm2", T::kNumber, "um/mm^2", "finite", "0",
          "Polynomial: envelope c2")
          .Default("0.0")
          .Example("1.0"),
      Key("waveform.c_um", T::kNumber, "um/mm^alpha", "finite", "0", "Fractional: envelope c")
          .Default("0.0")
          .Example("300.0")
          .When(kFractionalWave),
      Key("waveform.alpha", T::kNumber, "", "(0, 1]", "0.5", "Fractional: envelope exponent alpha")
          .Default("0.5")
          .Refused("0")
          .When(kFractionalWave),
      Key("waveform.frequency_Hz", T::kNumber, "Hz", "finite and != 0", "0.01",
          "Wave frequency f; < 0 sends the wave tail-to-head")
          .Default("0.01")
          .Refused("0"),
      Key("waveform.wavelength_mm", T::kNumber, "mm", "finite and > 0", "32",
          "Wavelength lambda")
          .Default("32.0")
          .Refused("0"),
      Key("waveform.start_ramp_cycles", T::kNumber, "", "[0, cycles]", "0.25",
          "The references fade in by (1 - cos(pi t / T_r)) / 2 over T_r = this / f")
          .Default("0.25")
          .Refused("-1"),
      Key("fluid.viscosity_Pa_s", T::kNumber, "Pa s", "> 0", "the model's `ipmc_rft_viscosity_Pa_s`",
          "Dynamic viscosity of the fluid, overriding the model's")
          .Example("1e-3")
          .Refused("0")
          .Above(0.0),
      Key("output.dir", T::kString, "", "a directory; relative to the working directory",
          "\"\": no files", "Where timeseries.csv, states.csv and summary.json go")
          .Default("\"\""),
      Key("output.samples_per_cycle", T::kInteger, "", ">= 1", "200",
          "Time-series samples per wave period")
          .Default("200")
          .Refused("0")
          .AtLeast(1)
          .AtMost(INT_MAX),
  };
}

std::vector<KeySpec> MakeSweepFileKeys() {
  using T = KeyType;
  return {
      Key("base", T::kString, "", "a scenario file; relative to the sweep file's folder",
          "none: required", "The scenario every point starts from"),
      Key("set", T::kTable, "", "scenario keys (dotted, or as nested tables)", "none",
          "Overrides applied to every point (not columns of the table)"),
      Key("grid", T::kTable, "", "scenario keys, each an array of values; not with point",
          "none", "The Cartesian product of the arrays, the first key outermost"),
      Key("point", T::kTableArray, "", "tables of scenario keys; not with grid", "none",
          "One point per [[point]] table, in file order"),
  };
}

// `text` with '|' escaped for a Markdown table cell.
std::string Cell(const std::string& text) {
  std::string cell;
  for (char c : text) {
    if (c == '|') cell += '\\';
    cell += c;
  }
  return cell;
}

void AppendMarkdown(const std::vector<KeySpec>& keys, std::string* out) {
  *out += "| key | type | unit | allowed | default | meaning |\n";
  *out += "|---|---|---|---|---|---|\n";
  for (const KeySpec& key : keys) {
    *out += "| `" + std::string(key.name) + "` | " + KeyTypeName(key.type) + " | " +
            Cell(key.unit) + " | " + Cell(key.allowed) + " | " + Cell(key.default_text) + " | " +
            Cell(key.meaning) + " |\n";
  }
}

void AppendText(const std::vector<KeySpec>& keys, std::string* out) {
  for (const KeySpec& key : keys) {
    std::string head = "  " + std::string(key.name) + " (" + KeyTypeName(key.type);
    if (*key.unit != '\0') head += ", " + std::string(key.unit);
    *out += head + "): " + key.allowed + "; default " + key.default_text + "\n";
    *out += "      " + std::string(key.meaning) + "\n";
  }
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

std::string KeyReference(KeyFormat format) {
  std::string out;
  if (format == KeyFormat::kMarkdown) {
    out += "# Scenario and sweep keys\n\n";
    out += "Generated by `ipmc-swim keys --format markdown`; a test fails when this file and\n"
           "the program differ.\n\n";
    out += "## Scenario keys\n\n";
    out += "Scenario files (TOML) set these keys; `[controller]` holds the `controller.*`\n"
           "keys, and so on. Sweep files' `[set]`, `[grid]` and `[[point]]` and\n"
           "`ipmc-swim run --set KEY=VALUE` take the same dotted names. Keys of the other\n"
           "kind of a table (a PID gain with `controller.kind = \"fractional\"`) are errors.\n\n";
    AppendMarkdown(ScenarioKeys(), &out);
    out += "\n## Sweep-file keys\n\n";
    AppendMarkdown(SweepFileKeys(), &out);
  } else {
    out += "Scenario keys (scenario files; sweep [set], [grid], [[point]]; run --set KEY=VALUE):\n";
    AppendText(ScenarioKeys(), &out);
    out += "\nSweep-file keys:\n";
    AppendText(SweepFileKeys(), &out);
  }
  return out;
}

}  // namespace ipmc
