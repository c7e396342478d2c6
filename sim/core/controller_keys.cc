#include "sim/core/controller_keys.h"

#include <cstddef>
#include <string>

#include "controllers/controller_names.h"
#include "controllers/fractional_integrator.h"
#include "sim/base/numbers.h"
#include "sim/core/key_builder.h"
#include "sim/core/scenario.h"

namespace ipmc {
namespace {

// Selectors and the values they choose between.
constexpr char kControllerKind[] = "controller.kind";
constexpr char kRealisation[] = "controller.realisation";
constexpr const char* kPid = controller_names::kPid;
constexpr const char* kFractional = controller_names::kFractional;
constexpr char kOustaloup[] = "oustaloup";

bool IsPid(const ScenarioConfig& config) { return config.controller.kind == ControllerKind::kPid; }

// Oustaloup's band [w_b, w_h], 0 < w_b < w_h.
void ReadBand(const KeyValue& value, ScenarioConfig& config) {
  const std::string expected = "an array of two numbers [w_b, w_h]";
  const std::size_t count = value.ArraySize(expected);
  if (count != 2) {
    value.Fail(value.name() + " must be " + expected + " (got " + std::to_string(count) + ")",
               "two numbers [w_b, w_h]");
  }
  const double low = value.NumberAt(0), high = value.NumberAt(1);
  if (!(low < high)) {
    value.Fail(value.name() + " must have w_b < w_h (got [" + FormatShortest(low) + ", " +
                   FormatShortest(high) + "])",
               "w_b < w_h");
  }
  config.controller.fractional.w_low_rad_s = low;
  config.controller.fractional.w_high_rad_s = high;
}

// controller.link_*: one gain per link overriding controller.<scalar> for
// that link; each value in the scalar key's range.
template <std::vector<double> ControllerScenario::LinkGains::*kField>
Key LinkGainKey(const char* name, const char* unit, const char* allowed, const char* meaning,
                const char* example_toml) {
  return PerLinkKey<ControllerScenario, ControllerScenario::LinkGains, &ScenarioConfig::controller,
                    &ControllerScenario::link_gains, kField>(name, unit, allowed, meaning,
                                                             example_toml);
}

// The keys of every controller kind: the kind, the sample rate, the clamp.
std::vector<KeySpec> CommonKeys() {
  using T = KeyType;
  return {
      Key(kControllerKind, T::kChoice, "", "", "\"pid\"",
          "pid: eq. 12 per link; fractional: K / s^lambda per link (eq. 13-15)")
          .Default("\"pid\"")
          .Example("\"fractional\"")
          .Refused("\"lqr\"")
          .Choices(kControllerKindNames)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.controller.kind = ChoiceValue(kControllerKindNames, v.Choice());
          })
          .Writes([](const ScenarioConfig& c) {
            return TomlString(ChoiceText(kControllerKindNames, c.controller.kind));
          }),
      Key(kSampleRateKey, T::kNumber, "Hz", "> 0; a whole number of time steps per sample", "1000",
          "Controller sample rate (the data-acquisition board's)")
          .Default("1000.0")
          .Refused("0")
          .Above(0.0)
          .Fields("sample_period_s")
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.controller.sample_rate_Hz = v.Number();
          })
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.controller.sample_rate_Hz); }),
      Key("controller.v_max_V", T::kNumber, "V", "> 0", "6", "Output voltage limit")
          .Default("6.0")
          .Refused("0")
          .Above(0.0)
          .Fields("v_max")
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.controller.pid.v_max = c.controller.fractional.v_max = v.Number();
          })
          .Writes([](const ScenarioConfig& c) {
            return TomlFloat(IsPid(c) ? c.controller.pid.v_max : c.controller.fractional.v_max);
          }),
      Key("controller.clamp", T::kBoolean, "", "true or false", "true",
          "Clamp the output to +-v_max_V with anti-windup; false: the linear loop")
          .Default("true")
          .Example("false")
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.controller.pid.clamp_enabled = c.controller.fractional.clamp_enabled = v.Boolean();
          })
          .Writes([](const ScenarioConfig& c) {
            return TomlBool(IsPid(c) ? c.controller.pid.clamp_enabled
                                     : c.controller.fractional.clamp_enabled);
          }),
  };
}

// PID (eq. 12): the gains, one set or one per link.
std::vector<KeySpec> PidKeys() {
  using T = KeyType;
  return {
      Key("controller.kp", T::kNumber, "V/mm", ">= 0", "8.12", "PID: proportional gain Kp")
          .Default("8.12")
          .Refused("-1")
          .AtLeast(0.0)
          .Only(kControllerKind, kPid)
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.controller.pid.kp = v.Number(); })
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.controller.pid.kp); }),
      Key("controller.ki", T::kNumber, "V/(mm s)", ">= 0", "53.36", "PID: integral gain Ki")
          .Default("53.36")
          .Refused("-1")
          .AtLeast(0.0)
          .Only(kControllerKind, kPid)
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.controller.pid.ki = v.Number(); })
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.controller.pid.ki); }),
      Key("controller.kd", T::kNumber, "V s/mm", ">= 0", "0.61", "PID: derivative gain Kd")
          .Default("0.61")
          .Refused("-1")
          .AtLeast(0.0)
          .Only(kControllerKind, kPid)
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.controller.pid.kd = v.Number(); })
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.controller.pid.kd); }),
      LinkGainKey<&ControllerScenario::LinkGains::kp>(
          "controller.link_kp", "V/mm", "each >= 0",
          "One Kp per link, in order, over controller.kp (set by an optimisation that retunes "
          "each design's controllers)",
          "[10.3, 2.6, 1.2]")
          .Refused("[1, -1, 1]")
          .AtLeast(0.0)
          .Only(kControllerKind, kPid),
      LinkGainKey<&ControllerScenario::LinkGains::ki>(
          "controller.link_ki", "V/(mm s)", "each >= 0",
          "One Ki per link, in order, over controller.ki (set by an optimisation that retunes "
          "each design's controllers)",
          "[36, 9, 4]")
          .Refused("[1, -1, 1]")
          .AtLeast(0.0)
          .Only(kControllerKind, kPid),
      LinkGainKey<&ControllerScenario::LinkGains::kd>(
          "controller.link_kd", "V s/mm", "each >= 0",
          "One Kd per link, in order, over controller.kd (set by an optimisation that retunes "
          "each design's controllers)",
          "[0.57, 0.14, 0.06]")
          .Refused("[1, -1, 1]")
          .AtLeast(0.0)
          .Only(kControllerKind, kPid),
      Key("controller.derivative_filter_s", T::kNumber, "s", ">= 0", "0",
          "PID: derivative filter time constant Tf (0: the ideal derivative)")
          .Default("0.0")
          .Example("0.01")
          .Refused("-1")
          .AtLeast(0.0)
          .Only(kControllerKind, kPid)
          .Fields("derivative_filter_time_s")
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.controller.pid.derivative_filter_time_s = v.Number();
          })
          .Writes([](const ScenarioConfig& c) {
            return TomlFloat(c.controller.pid.derivative_filter_time_s);
          }),
  };
}

// The fractional integrator (eq. 13-15): its gain, order and realisation.
std::vector<KeySpec> FractionalKeys() {
  using T = KeyType;
  return {
      Key("controller.gain", T::kNumber, "V/(mm s^lambda)", ">= 0", "15.62", "Fractional: gain K")
          .Default("15.62")
          .Refused("-1")
          .AtLeast(0.0)
          .Only(kControllerKind, kFractional)
          .Only(kRealisation, kOustaloup)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.controller.fractional.gain = v.Number();
          })
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.controller.fractional.gain); }),
      Key("controller.order", T::kNumber, "", "(0, 1]", "0.62", "Fractional: order lambda")
          .Default("0.62")
          .Refused("1.5")
          .Above(0.0)
          .AtMost(1.0)
          .Only(kControllerKind, kFractional)
          .Only(kRealisation, kOustaloup)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.controller.fractional.order = v.Number();
          })
          .Writes([](const ScenarioConfig& c) { return TomlFloat(c.controller.fractional.order); }),
      LinkGainKey<&ControllerScenario::LinkGains::gain>(
          "controller.link_gain", "V/(mm s^lambda)", "each >= 0",
          "One K per link, in order, over controller.gain (set by an optimisation that retunes "
          "each design's controllers)",
          "[14.6, 3.7, 1.6]")
          .Refused("[1, -1, 1]")
          .AtLeast(0.0)
          .Only(kControllerKind, kFractional)
          .Only(kRealisation, kOustaloup),
      LinkGainKey<&ControllerScenario::LinkGains::order>(
          "controller.link_order", "", "each in (0, 1]",
          "One lambda per link, in order, over controller.order (set by an optimisation that "
          "retunes each design's controllers)",
          "[0.59, 0.59, 0.59]")
          .Refused("[0.5, 1.5, 0.5]")
          .Above(0.0)
          .AtMost(1.0)
          .Only(kControllerKind, kFractional)
          .Only(kRealisation, kOustaloup),
      Key("controller.oustaloup_n", T::kInteger, "", "[1, 64]", "4",
          "Fractional: Oustaloup pole-zero pairs N")
          .Default("4")
          .Refused("0")
          .AtLeast(1)
          .AtMost(kMaxOustaloupPairs)
          .Only(kControllerKind, kFractional)
          .Only(kRealisation, kOustaloup)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.controller.fractional.oustaloup_n = v.Integer();
          })
          .Writes([](const ScenarioConfig& c) {
            return TomlInteger(c.controller.fractional.oustaloup_n);
          }),
      Key("controller.band_rad_s", T::kNumberArray, "rad/s",
          "two numbers [w_b, w_h], 0 < w_b < w_h", "[1e-3, 1e2]",
          "Fractional: Oustaloup's fitting band")
          .Default("[1e-3, 1e2]")
          .Refused("[10, 1]")
          .Above(0.0)
          .Only(kControllerKind, kFractional)
          .Only(kRealisation, kOustaloup)
          .Fields("w_low_rad_s w_high_rad_s")
          .Reads(ReadBand)
          .Writes([](const ScenarioConfig& c) {
            return TomlFloats(
                {c.controller.fractional.w_low_rad_s, c.controller.fractional.w_high_rad_s});
          }),
      Key(kRealisation, T::kChoice, "", "\"oustaloup\" or \"eq15\"", "\"oustaloup\"",
          "Fractional: oustaloup (K / s^lambda on the band) or eq15 (the paper's printed eq. "
          "15; no gain, order, link_gain, link_order, oustaloup_n or band_rad_s)")
          .Default("\"oustaloup\"")
          .Example("\"eq15\"")
          .Refused("\"tustin\"")
          .Choices("oustaloup|eq15")
          .Only(kControllerKind, kFractional)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.controller.fractional.realisation = *ParseFractionalRealisation(v.Choice());
          })
          .Writes([](const ScenarioConfig& c) {
            return TomlString(FractionalRealisationName(c.controller.fractional.realisation));
          }),
  };
}

}  // namespace

void ControllerScenario::SetSamplePeriod() {
  pid.sample_period_s = 1.0 / sample_rate_Hz;
  fractional.sample_period_s = 1.0 / sample_rate_Hz;
}

PidController::Config ControllerScenario::LinkPid(int q) const {
  PidController::Config config = pid;
  if (!link_gains.kp.empty()) config.kp = link_gains.kp.at(q);
  if (!link_gains.ki.empty()) config.ki = link_gains.ki.at(q);
  if (!link_gains.kd.empty()) config.kd = link_gains.kd.at(q);
  return config;
}

FractionalIntegrator::Config ControllerScenario::LinkFractional(int q) const {
  FractionalIntegrator::Config config = fractional;
  if (!link_gains.gain.empty()) config.gain = link_gains.gain.at(q);
  if (!link_gains.order.empty()) config.order = link_gains.order.at(q);
  return config;
}

void ControllerScenario::Validate() const {
  if (kind == ControllerKind::kPid) {
    pid.Validate();
  } else {
    fractional.Validate();
  }
}

std::vector<KeySpec> ControllerKeys() {
  static_assert(kMaxOustaloupPairs == 64, "the allowed range of oustaloup_n states this limit");
  std::vector<KeySpec> keys = CommonKeys();
  for (const std::vector<KeySpec>& part : {PidKeys(), FractionalKeys()}) {
    keys.insert(keys.end(), part.begin(), part.end());
  }
  return keys;
}

}  // namespace ipmc
