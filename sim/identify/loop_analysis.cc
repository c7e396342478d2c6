#include "sim/identify/loop_analysis.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <nlohmann/json.hpp>

#include "controllers/controller_names.h"
#include "controllers/fractional_integrator.h"
#include "sim/linear/oustaloup.h"
#include "sim/linear/state_space.h"
#include "controllers/paper_eq15.h"
#include "controllers/pid.h"
#include "controllers/reference_model.h"
#include "sim/linear/ipmc_link_model.h"
#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/core/scenario_simulation.h"
#include "sim/core/simulation.h"
#include "sim/identify/controller_design.h"
#include "sim/identify/key_files.h"
#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/io/files.h"
#include "sim/runs/closed_loop_run.h"

namespace ipmc {
namespace {

// The margins the bode command prints (the root search of
// sim/linear/frequency_response.h), null where there is none; the
// Bode figure marks these.
nlohmann::json MarginsJson(const StabilityMargins& margins) {
  const auto number = [](const std::optional<double>& value) {
    return value ? nlohmann::json(*value) : nlohmann::json();
  };
  return {{"gain_crossover_rad_s", number(margins.gain_crossover_rad_s)},
          {"phase_margin_deg", number(margins.phase_margin_deg)},
          {"phase_crossover_rad_s", number(margins.phase_crossover_rad_s)},
          {"gain_margin_dB", number(margins.gain_margin_dB)}};
}

using Complex = std::complex<double>;

using controller_names::kFractional;
using controller_names::kFractionalEq15;
using controller_names::kFractionalOustaloup;
using controller_names::kNone;
using controller_names::kPid;

// The controllers are compared at the reference model's crossover.
constexpr double kDesignFrequency_rad_s = 5.0;

constexpr double kSettlingBand = 0.02;
// Samples per link in a step run (memory: three doubles per sample).
constexpr double kMaxStepSamples = 1e6;

// Gains and bands in descriptions: printf's %g.
std::string Short(double value) { return FormatDouble(value, 6); }

void RequireLink(const std::string& command, const std::string& option, int link,
                 int max_links = 3) {
  if (link < 1 || link > max_links) {
    ThrowOption(command, option,
                max_links == 3 ? "1, 2 or 3" : "in 1.." + std::to_string(max_links),
                std::to_string(link));
  }
}

}  // namespace

void ValidateLinkList(const std::string& command, const std::vector<int>& links, int max_links) {
  if (links.empty()) {
    ThrowOption(command, "links", "a list of links 1.." + std::to_string(max_links), "none");
  }
  for (std::size_t i = 0; i < links.size(); ++i) {
    RequireLink(command, "links", links[i], max_links);
    if (std::count(links.begin(), links.begin() + i, links[i]) > 0) {
      ThrowOption(command, "links", "distinct", "link " + std::to_string(links[i]) + " twice");
    }
  }
}

namespace {

void RequirePlant(const std::string& command, const std::string& plant) {
  if (plant != "g1" && plant != "g2") ThrowOption(command, "plant", "g1 or g2", plant);
}

// Rejects an option the chosen controller does not take, so that a gain
// given to the wrong controller is not silently ignored.
void RejectIfGiven(const std::string& command, const OptionGiven& given,
                   const std::string& option, bool applies, const std::string& controller) {
  if (!applies && given && given(option)) {
    throw FieldError(command + ": " + option + " does not apply to controller " + controller,
                     option, "");
  }
}

void ValidatePidGains(const std::string& command, const ControllerGains& gains) {
  const std::pair<const char*, double> terms[] = {
      {"kp", gains.kp}, {"ki", gains.ki}, {"kd", gains.kd}};
  for (const auto& [option, value] : terms) {
    if (!std::isfinite(value) || value < 0) {
      ThrowOption(command, option, "finite and >= 0", FormatDouble(value));
    }
  }
  if (gains.kp == 0 && gains.ki == 0 && gains.kd == 0) {
    throw FieldError(command + ": at least one of kp, ki, kd must be > 0", "kp", "> 0");
  }
}

void ValidateFractionalGains(const std::string& command, const ControllerGains& gains) {
  RequireFinitePositive(command, "gain", gains.gain);
  if (!std::isfinite(gains.order) || !(gains.order > 0) || gains.order > 1) {
    ThrowOption(command, "order", "in (0, 1]", FormatDouble(gains.order));
  }
}

IpmcModelKind PlantKind(const std::string& plant) {
  return plant == "g2" ? IpmcModelKind::kG2 : IpmcModelKind::kG1;
}

std::string PlantDescription(const IpmcLinkParams& p, int link, const std::string& source) {
  std::ostringstream text;
  text << "P(s) = s^-0.5 ";
  if (p.kind == IpmcModelKind::kG1) {
    text << "G1(s), G1 = " << Short(p.a0_mm_per_V) << " / (" << Short(p.b2_s2) << " s^2 + "
         << Short(p.b1) << " s + 1)";
    if (link == 3 && source.empty()) text << " (eq. 7)";
  } else {
    text << "G2(s), G2 = " << Short(p.a0_mm_per_V) << " / (" << Short(p.b1) << " s^"
         << Short(p.alpha) << " + 1)";
  }
  text << " [mm/V], link " << link;
  if (!source.empty()) text << " (" << source << ")";
  return text.str();
}

// The link's plant: its own, else Table 2's.
IpmcLinkParams LinkPlant(const std::optional<IpmcLinkParams>& own, const std::string& plant,
                         int link) {
  return own ? *own : PaperLinkParams(link, PlantKind(plant));
}

PidController::Config PidConfig(const ControllerGains& gains) {
  PidController::Config config;
  config.kp = gains.kp;
  config.ki = gains.ki;
  config.kd = gains.kd;
  config.derivative_filter_time_s = gains.derivative_filter_s;
  return config;
}

std::string PidDescription(const ControllerGains& gains) {
  return "C(s) = " + Short(gains.kp) + " + " + Short(gains.ki) + "/s + " + Short(gains.kd) +
         (gains.derivative_filter_s > 0
              ? " s / (" + Short(gains.derivative_filter_s) + " s + 1)"
              : std::string(" s"));
}

std::string FractionalDescription(const ControllerGains& gains) {
  return "C(s) = " + Short(gains.gain) + " / s^" + Short(gains.order);
}

struct ControllerResponse {
  FrequencyFunction response;
  std::string description;
};

ControllerResponse BodeController(const BodeSpec& spec) {
  const std::string& c = spec.controller;
  if (c == kPid) {
    const PidController pid(PidConfig(spec.gains));
    return {[pid](double w) { return pid.Evaluate({0.0, w}); },
            PidDescription(spec.gains) +
                (spec.gains.derivative_filter_s > 0 ? " (eq. 10, filtered derivative)"
                                                    : " (eq. 10, ideal derivative)") +
                (spec.gains_source.empty() ? "" : " (" + spec.gains_source + ")")};
  }
  if (c == kFractional || c == kFractionalOustaloup) {
    FractionalIntegrator::Config config;
    config.gain = spec.gains.gain;
    config.order = spec.gains.order;
    config.oustaloup_n = spec.oustaloup_n;
    config.w_low_rad_s = spec.band_rad_s[0];
    config.w_high_rad_s = spec.band_rad_s[1];
    const FractionalIntegrator integrator(config);
    if (c == kFractional) {
      return {[integrator](double w) { return integrator.EvaluateExact({0.0, w}); },
              FractionalDescription(spec.gains) + " (eq. 13, exact)" +
                  (spec.gains_source.empty() ? "" : " (" + spec.gains_source + ")")};
    }
    return {[integrator](double w) { return integrator.Evaluate({0.0, w}); },
            FractionalDescription(spec.gains) + " by Oustaloup, " +
                std::to_string(spec.oustaloup_n) + " pairs on [" + Short(spec.band_rad_s[0]) +
                ", " + Short(spec.band_rad_s[1]) + "] rad/s"};
  }
  if (c == kFractionalEq15) {
    return {[](double w) { return Eq15Evaluate({0.0, w}); }, Eq15Description()};
  }
  return {[](double) { return Complex(1.0, 0.0); }, "C(s) = 1 (no controller)"};
}

// How far a link's record may be extended for its metrics: max_horizon_s
// within the sample budget, and never short of the horizon.
double MetricsHorizon_s(const StepSpec& spec) {
  const double budget_s = kMaxStepSamples / spec.sample_rate_Hz;
  return std::max(spec.horizon_s, std::min(spec.max_horizon_s, budget_s));
}

// The gains of link `link`: its own (a gains file's), else the spec's.
const ControllerGains& StepGains(const StepSpec& spec, int link) {
  return spec.link_gains.empty() ? spec.gains : spec.link_gains.at(link - 1);
}

// Link `link`'s controllers as the step runs them: its gains, the spec's
// rate and clamp; s^-lambda as the accurate Oustaloup realisation.
PidController::Config StepPidConfig(const StepSpec& spec, int link) {
  PidController::Config config = PidConfig(StepGains(spec, link));
  config.sample_period_s = 1.0 / spec.sample_rate_Hz;
  config.clamp_enabled = !spec.no_clamp;
  config.v_max = spec.v_max_V;
  return config;
}
FractionalIntegrator::Config StepFractionalConfig(const StepSpec& spec, int link) {
  const ControllerGains& gains = StepGains(spec, link);
  FractionalIntegrator::Config config;
  config.gain = gains.gain;
  config.order = gains.order;
  config.oustaloup_n = kAccurateOustaloupPairs;
  config.w_low_rad_s = kAccurateBandLow_rad_s;
  config.w_high_rad_s = kAccurateBandHigh_rad_s;
  config.sample_period_s = 1.0 / spec.sample_rate_Hz;
  config.clamp_enabled = !spec.no_clamp;
  config.v_max = spec.v_max_V;
  return config;
}

ClosedLoopResponse SimulateLink(const StepSpec& spec, int link) {
  const StateSpace plant = AccurateLinkPlant(
      spec.own_plants.empty() ? PaperLinkParams(link, PlantKind(spec.plant))
                              : spec.own_plants.at(link - 1));
  StepSimulation simulation;
  simulation.horizon_s = spec.horizon_s;
  simulation.max_horizon_s = MetricsHorizon_s(spec);
  simulation.settling_band = kSettlingBand;
  if (spec.controller == kPid) {
    PidController pid(StepPidConfig(spec, link));
    return SimulateClosedLoopStep(plant, pid, simulation);
  }
  FractionalIntegrator integrator(StepFractionalConfig(spec, link));
  return SimulateClosedLoopStep(plant, integrator, simulation);
}

// The bench scenario with the step's controllers on every link (its kind,
// gains, rate and clamp; the per-link gains of a gains file), one wave
// period of horizon_s and a sample (the run's length, samples t_k = k T up
// to the horizon's; the wave itself is not used), every controller sample
// recorded and no files.
ScenarioConfig BenchScenario(const StepSpec& spec, const ScenarioConfig& bench) {
  ScenarioConfig scenario = bench;
  ControllerScenario& controller = scenario.controller;
  controller.kind = spec.controller == kPid ? ControllerKind::kPid : ControllerKind::kFractional;
  controller.sample_rate_Hz = spec.sample_rate_Hz;
  const int first = spec.links.front();
  controller.pid = StepPidConfig(spec, first);
  controller.fractional = StepFractionalConfig(spec, first);
  controller.link_gains = {};
  for (const ControllerGains& gains : spec.link_gains) {
    controller.link_gains.kp.push_back(gains.kp);
    controller.link_gains.ki.push_back(gains.ki);
    controller.link_gains.kd.push_back(gains.kd);
    controller.link_gains.gain.push_back(gains.gain);
    controller.link_gains.order.push_back(gains.order);
  }
  controller.SetSamplePeriod();
  scenario.actuation = Actuation::kDistributed;
  scenario.run.cycles = 1;
  const long samples = std::lround(std::ceil(spec.horizon_s * spec.sample_rate_Hz - 1e-9)) + 1;
  scenario.waveform.frequency_Hz = spec.sample_rate_Hz / static_cast<double>(samples);
  scenario.metrics.from_cycle = 1;
  scenario.output.dir.clear();
  scenario.output.samples_per_cycle = static_cast<int>(samples);
  return scenario;
}

// Link `link`'s unit step on the bench's multibody simulation, the other
// links' references held at 0, as a step record (one point per sample).
ClosedLoopResponse SimulateBenchLink(const ScenarioConfig& scenario, int link) {
  const std::unique_ptr<Simulation> sim = LoadScenarioSimulation(scenario);
  std::vector<double> references(static_cast<std::size_t>(ScenarioLinkCount(scenario)), 0.0);
  references.at(static_cast<std::size_t>(link - 1)) = 1.0;
  const LinkReferenceSource step = [&references](double) { return references; };
  const ClosedLoopResult run = StepClosedLoop(*sim, scenario, {}, {}, step);
  ClosedLoopResponse response;
  response.sample_period_s = 1.0 / scenario.controller.sample_rate_Hz;
  for (std::size_t k = 0; k < run.samples.size(); ++k) {
    response.time_s.push_back(static_cast<double>(k) * response.sample_period_s);
    response.output.push_back(run.samples[k].measured_mm.at(link - 1));
    response.control.push_back(run.samples[k].voltage_V.at(link - 1));
  }
  return response;
}

// The first `points` of a link's record (the horizon's, shared by all).
std::size_t HorizonPoints(const std::vector<double>& time_s, double horizon_s,
                          double sample_period_s) {
  std::size_t points = 0;
  // The horizon's last point is the first sample at or after it.
  const double end_s = std::ceil(horizon_s / sample_period_s - 1e-9) * sample_period_s;
  while (points < time_s.size() && time_s[points] <= end_s * (1 + 1e-12)) ++points;
  return points;
}

TrackingIndices StepIndices(const ClosedLoopResponse& response, double horizon_s);

// A link's step record with its metrics, J of eq. 11 and Table 5's indices.
LinkStep EvaluateStep(int link, ClosedLoopResponse response, double horizon_s,
                      const ReferenceModel& model) {
  LinkStep step;
  step.link = link;
  step.response = std::move(response);
  step.metrics = ComputeStepMetrics(step.response, kSettlingBand);
  step.status = CheckStepRecord(step.response, kSettlingBand);
  for (double u : step.response.control) {
    step.max_abs_control_V = std::max(step.max_abs_control_V, std::abs(u));
  }
  step.cost = ReferenceModelCost(step.response, model, horizon_s);
  step.indices = StepIndices(step.response, horizon_s);
  return step;
}

// Table 5's IAE and ITAE of a unit step's error over the samples before
// the horizon (the record holds one point per sample from t = 0).
TrackingIndices StepIndices(const ClosedLoopResponse& response, double horizon_s) {
  const double period_s = response.sample_period_s;
  const std::size_t samples =
      HorizonPoints(response.time_s, horizon_s, period_s) - 1;  // t_k < the horizon's end
  TrackingIndices indices;
  for (std::size_t k = 0; k < samples; ++k) {
    indices.Add(response.time_s[k], 1.0 - response.output[k], period_s);
  }
  return indices;
}

}  // namespace

// ------------------------------------------------------------------ bode ---

void ValidateBodeSpec(const std::string& command, const BodeSpec& spec, const OptionGiven& given) {
  const std::string& name = command;
  const std::string& c = spec.controller;
  const bool known = c == kPid || c == kFractional || c == kFractionalEq15 ||
                     c == kFractionalOustaloup || c == kNone;
  if (!known) {
    ThrowOption(name, "controller",
                "pid, fractional, fractional-eq15, fractional-oustaloup or none", "'" + c + "'");
  }
  RequirePlant(name, spec.plant);
  RejectIfGiven(name, given, "kp", c == kPid, c);
  RejectIfGiven(name, given, "ki", c == kPid, c);
  RejectIfGiven(name, given, "kd", c == kPid, c);
  const bool fractional = c == kFractional || c == kFractionalOustaloup;
  RejectIfGiven(name, given, "gain", fractional, c);
  RejectIfGiven(name, given, "order", fractional, c);
  RejectIfGiven(name, given, "oustaloup_pairs", c == kFractionalOustaloup, c);
  RejectIfGiven(name, given, "band_rad_s", c == kFractionalOustaloup, c);
  if (c == kPid) ValidatePidGains(name, spec.gains);
  if (fractional) ValidateFractionalGains(name, spec.gains);
  if (spec.oustaloup_n < 1 || spec.oustaloup_n > kMaxOustaloupPairs) {
    ThrowOption(name, "oustaloup_pairs", "in [1, " + std::to_string(kMaxOustaloupPairs) + "]",
                std::to_string(spec.oustaloup_n));
  }
  if (spec.band_rad_s.size() != 2) {
    const std::size_t count = spec.band_rad_s.size();
    ThrowOption(name, "band_rad_s", "two frequencies LOW,HIGH",
                std::to_string(count) + (count == 1 ? " value" : " values"));
  }
  if (!std::isfinite(spec.band_rad_s[0]) || !(spec.band_rad_s[0] > 0)) {
    ThrowOption(name, "band_rad_s", "LOW,HIGH with LOW finite and > 0",
                FormatDouble(spec.band_rad_s[0]));
  }
  if (!std::isfinite(spec.band_rad_s[1]) || !(spec.band_rad_s[1] > spec.band_rad_s[0])) {
    ThrowOption(name, "band_rad_s", "LOW,HIGH with HIGH finite and > LOW",
                FormatDouble(spec.band_rad_s[1]));
  }
  RequireFinitePositive(name, "w_min_rad_s", spec.w_min_rad_s);
  if (!std::isfinite(spec.w_max_rad_s) || !(spec.w_max_rad_s > spec.w_min_rad_s)) {
    ThrowOption(name, "w_max_rad_s",
                "finite and > w_min_rad_s (" + FormatDouble(spec.w_min_rad_s) + ")",
                FormatDouble(spec.w_max_rad_s));
  }
  if (spec.points_per_decade < 1 || spec.points_per_decade > 100000) {
    ThrowOption(name, "points_per_decade", "in [1, 100000]",
                std::to_string(spec.points_per_decade));
  }
}

BodeAnalysis AnalyseBode(const BodeSpec& spec) {
  BodeAnalysis analysis;
  const IpmcLinkParams params = LinkPlant(spec.own_plant, spec.plant, spec.link);
  analysis.plant = [params](double w) { return LinkResponseExact(params, w); };
  ControllerResponse controller = BodeController(spec);
  analysis.controller = controller.response;
  analysis.controller_description = std::move(controller.description);
  analysis.plant_description = PlantDescription(params, spec.link, spec.plant_source);
  analysis.loop = [plant = analysis.plant, c = analysis.controller](double w) {
    return c(w) * plant(w);
  };
  analysis.margins = ComputeMargins(analysis.loop, analysis.search);
  analysis.design_frequency_rad_s = kDesignFrequency_rad_s;
  analysis.controller_at_design = analysis.controller(kDesignFrequency_rad_s);
  analysis.plant_at_design = analysis.plant(kDesignFrequency_rad_s);
  return analysis;
}

BodeColumns ComputeBodeColumns(const BodeAnalysis& analysis, const BodeSpec& spec) {
  FrequencyGrid grid;
  grid.w_low_rad_s = spec.w_min_rad_s;
  grid.w_high_rad_s = spec.w_max_rad_s;
  grid.points_per_decade = spec.points_per_decade;
  const ReferenceModel model;
  BodeColumns columns;
  columns.plant = ComputeBode(analysis.plant, grid);
  columns.controller = ComputeBode(analysis.controller, grid);
  columns.open_loop = ComputeBode(analysis.loop, grid);
  columns.reference_open_loop =
      ComputeBode([&model](double w) { return model.OpenLoop({0.0, w}); }, grid);
  return columns;
}

void WriteBodeCsv(const BodeData& bode, const std::filesystem::path& path) {
  const std::size_t n = bode.w_rad_s.size();
  if (bode.magnitude_dB.size() != n || bode.phase_deg.size() != n) {
    throw std::invalid_argument(
        "WriteBodeCsv: w_rad_s, magnitude_dB and phase_deg must have equal "
        "lengths, got " +
        std::to_string(n) + ", " + std::to_string(bode.magnitude_dB.size()) +
        ", " + std::to_string(bode.phase_deg.size()));
  }
  CsvWriter csv;
  csv.Row({columns::kFrequency, columns::kMagnitudeDb, columns::kPhaseDeg});
  for (std::size_t i = 0; i < n; ++i) {
    csv.Add(bode.w_rad_s[i]).Add(bode.magnitude_dB[i]).Add(bode.phase_deg[i]).EndRow();
  }
  WriteFileAtomically(path.string(), csv.Text());
}

std::string BodeCsv(const BodeColumns& bode) {
  const BodeData* responses[] = {&bode.plant, &bode.controller, &bode.open_loop,
                                 &bode.reference_open_loop};
  const char* curves[] = {columns::kPlantCurve, columns::kControllerCurve,
                          columns::kOpenLoopCurve, columns::kReferenceOpenLoopCurve};
  std::ostringstream csv;
  csv << std::setprecision(12);
  csv << columns::kFrequency;
  for (const char* curve : curves) {
    csv << "," << columns::MagnitudeDb(curve) << "," << columns::PhaseDeg(curve);
  }
  csv << "\n";
  for (std::size_t i = 0; i < bode.plant.w_rad_s.size(); ++i) {
    csv << bode.plant.w_rad_s[i];
    for (const BodeData* column : responses) {
      csv << "," << column->magnitude_dB[i] << "," << column->phase_deg[i];
    }
    csv << "\n";
  }
  return csv.str();
}

// ------------------------------------------------------------------ step ---

void ValidateStepSpec(const std::string& command, const StepSpec& spec, const OptionGiven& given) {
  const std::string& name = command;
  const std::string& c = spec.controller;
  if (c != kPid && c != kFractional) {
    ThrowOption(name, "controller", "pid or fractional", "'" + c + "'");
  }
  RequirePlant(name, spec.plant);
  RejectIfGiven(name, given, "kp", c == kPid, c);
  RejectIfGiven(name, given, "ki", c == kPid, c);
  RejectIfGiven(name, given, "kd", c == kPid, c);
  RejectIfGiven(name, given, "gain", c == kFractional, c);
  RejectIfGiven(name, given, "order", c == kFractional, c);
  if (spec.no_clamp && given && given("v_max_V")) {
    throw FieldError(name + ": v_max_V does not apply with no_clamp", "v_max_V", "");
  }
  const std::vector<ControllerGains> each =
      spec.link_gains.empty() ? std::vector<ControllerGains>{spec.gains} : spec.link_gains;
  for (const ControllerGains& gains : each) {
    if (c == kPid) ValidatePidGains(name, gains);
    if (c == kFractional) ValidateFractionalGains(name, gains);
  }
  const std::size_t links = std::max(spec.own_plants.size(), spec.link_gains.size());
  ValidateLinkList(name, spec.links, links > 0 ? static_cast<int>(links) : 3);
  RequireFinitePositive(name, "horizon_s", spec.horizon_s);
  RequireFinitePositive(name, "sample_rate_Hz", spec.sample_rate_Hz);
  if (spec.horizon_s * spec.sample_rate_Hz > kMaxStepSamples) {
    ThrowOption(name, "horizon_s",
                "at most " + Short(kMaxStepSamples) + " samples (horizon_s x sample_rate_Hz)",
                FormatDouble(spec.horizon_s * spec.sample_rate_Hz));
  }
  if (!spec.no_clamp) RequireFinitePositive(name, "v_max_V", spec.v_max_V);
  RequireFinitePositive(name, "max_horizon_s", spec.max_horizon_s);
}

StepAnalysis AnalyseStep(const StepSpec& spec) {
  const ReferenceModel model;
  StepAnalysis analysis;
  analysis.settling_band = kSettlingBand;
  analysis.oustaloup_pairs = kAccurateOustaloupPairs;
  analysis.band_low_rad_s = kAccurateBandLow_rad_s;
  analysis.band_high_rad_s = kAccurateBandHigh_rad_s;
  analysis.metrics_horizon_s = MetricsHorizon_s(spec);
  const auto describe = [&spec](const ControllerGains& gains) {
    return spec.controller == kPid ? PidDescription(gains) + " (eq. 10)"
                                   : FractionalDescription(gains) + " (eq. 13)";
  };
  if (spec.link_gains.empty()) {
    analysis.controller_description = describe(spec.gains);
  } else {
    analysis.controller_description = "per link (" + spec.gains_source + ")";
    for (int link : spec.links) {
      analysis.controller_description +=
          "; link " + std::to_string(link) + ": " + describe(StepGains(spec, link));
    }
  }

  for (int link : spec.links) {
    analysis.links.push_back(EvaluateStep(link, SimulateLink(spec, link), spec.horizon_s, model));
  }
  if (spec.bench) {
    const ScenarioConfig bench = BenchScenario(spec, *spec.bench);
    for (int link : spec.links) {
      analysis.bench.push_back(
          EvaluateStep(link, SimulateBenchLink(bench, link), spec.horizon_s, model));
    }
  }

  // The reference model on the horizon's time grid (the links share it;
  // their records may go on past it for their metrics).
  const ClosedLoopResponse& first = analysis.links.front().response;
  const std::size_t horizon_points =
      HorizonPoints(first.time_s, spec.horizon_s, first.sample_period_s);
  analysis.time_s.assign(first.time_s.begin(), first.time_s.begin() + horizon_points);
  analysis.reference.resize(horizon_points);
  for (std::size_t i = 0; i < horizon_points; ++i) {
    analysis.reference[i] = model.StepResponse(analysis.time_s[i]);
  }
  // The reference model's metrics: its exact first peak where the horizon
  // holds it.
  analysis.reference_metrics =
      ComputeStepMetrics(analysis.time_s, analysis.reference, 1.0, kSettlingBand);
  const std::optional<ReferenceModel::Peak> peak = model.StepPeak();
  if (peak && peak->time_s <= analysis.time_s.back()) {
    analysis.reference_metrics.peak_value = peak->value;
    analysis.reference_metrics.peak_time_s = peak->time_s;
    analysis.reference_metrics.overshoot_percent = 100.0 * (peak->value - 1.0);
  }
  return analysis;
}

std::string StepCsv(const StepAnalysis& analysis) {
  std::ostringstream csv;
  csv << std::setprecision(12);
  csv << "time_s,reference_model";
  for (const LinkStep& step : analysis.links) csv << ",y_link" << step.link;
  for (const LinkStep& step : analysis.links) csv << ",u_link" << step.link;
  csv << "\n";
  for (std::size_t i = 0; i < analysis.reference.size(); ++i) {
    csv << analysis.time_s[i] << "," << analysis.reference[i];
    for (const LinkStep& step : analysis.links) csv << "," << step.response.output[i];
    for (const LinkStep& step : analysis.links) csv << "," << step.response.control[i];
    csv << "\n";
  }
  return csv.str();
}

// ------------------------------------------------------ the commands ---

namespace {

const std::vector<std::string> kPlants = {"g1", "g2"};

// kp, ki, kd (PID) and gain, order (fractional integrator) of a spec
// holding `gains`.
template <typename Spec>
void AddGainOptions(OptionTable<Spec>& table) {
  table.template Add<double>({"kp", "V/mm", "finite and >= 0", "PID proportional gain"},
                             [](Spec& s) -> double& { return s.gains.kp; });
  table.template Add<double>({"ki", "V/(mm s)", "finite and >= 0", "PID integral gain"},
                             [](Spec& s) -> double& { return s.gains.ki; });
  table.template Add<double>({"kd", "V s/mm", "finite and >= 0", "PID derivative gain"},
                             [](Spec& s) -> double& { return s.gains.kd; });
  table.template Add<double>(
      {"gain", "V/(mm s^lambda)", "finite and > 0", "Fractional integrator gain K"},
      [](Spec& s) -> double& { return s.gains.gain; });
  table.template Add<double>({"order", "", "in (0, 1]", "Fractional integrator order lambda"},
                             [](Spec& s) -> double& { return s.gains.order; });
}

// --plant-file and --gains-file of bode and step.
template <typename Command>
void AddKeyFileOptions(OptionTable<Command>& table) {
  OptionInfo plant_file{"plant_file", "", "a TOML file of [plant] scenario keys",
                        "Each link's own plant from these keys (identify's plant.toml) instead "
                        "of Table 2's; links 1..n of its per-link keys"};
  plant_file.default_text = "none: Table 2";
  table.AddPath(plant_file, [](Command& c) -> std::string& { return c.plant_file; });
  OptionInfo gains_file{"gains_file", "", "a TOML file of [controller] scenario keys",
                        "Each link's own gains from these keys (design's gains.toml: "
                        "controller.link_kp, ...; derivative_filter_s) instead of kp, ki, kd, "
                        "gain, order"};
  gains_file.default_text = "none";
  table.AddPath(gains_file, [](Command& c) -> std::string& { return c.gains_file; });
}

// A gains file's controllers as each link's gains (1..n; `links` if it
// has no per-link arrays).
std::vector<ControllerGains> GainsOfKeyFile(const std::string& path, int links) {
  const KeyFileControllers controllers = ControllersOfKeyFile(path, links);
  std::vector<ControllerGains> gains(controllers.pid.size());
  for (std::size_t q = 0; q < gains.size(); ++q) {
    gains[q].kp = controllers.pid[q].kp;
    gains[q].ki = controllers.pid[q].ki;
    gains[q].kd = controllers.pid[q].kd;
    gains[q].derivative_filter_s = controllers.pid[q].derivative_filter_time_s;
    gains[q].gain = controllers.fractional[q].gain;
    gains[q].order = controllers.fractional[q].order;
  }
  return gains;
}

// The key files of a command: each link's plant and gains, checked for
// one link count, and kp ... order refused beside a gains file.
struct KeyFileLinksOf {
  std::vector<IpmcLinkParams> plants;
  std::vector<ControllerGains> gains;
  int links = 3;
  // The links to analyse: those given, else every link of the files.
  std::vector<int> Chosen(const std::vector<int>& links_option, const OptionGiven& given) const {
    if ((given && given("links")) || (plants.empty() && gains.empty())) return links_option;
    std::vector<int> all;
    for (int q = 1; q <= links; ++q) all.push_back(q);
    return all;
  }
};
template <typename Command>
KeyFileLinksOf ReadKeyFiles(const std::string& name, const Command& command,
                            const OptionGiven& given) {
  KeyFileLinksOf files;
  // A file without per-link arrays holds for any number of links: the
  // other file's, else 3.
  const bool plant_arrays = !command.plant_file.empty() && KeyFileHasLinkArrays(command.plant_file);
  const bool gains_arrays = !command.gains_file.empty() && KeyFileHasLinkArrays(command.gains_file);
  if (plant_arrays) files.links = KeyFileLinks(command.plant_file);
  if (gains_arrays && !plant_arrays) files.links = KeyFileLinks(command.gains_file);
  if (!command.gains_file.empty()) {
    for (const char* option : {"kp", "ki", "kd", "gain", "order"}) {
      if (given && given(option)) {
        throw FieldError(name + ": " + option + " does not apply with gains_file", option, "");
      }
    }
    files.gains = GainsOfKeyFile(command.gains_file, files.links);
  }
  if (!command.plant_file.empty()) {
    files.plants = PlantsOfKeyFile(command.plant_file, files.links);
    if (!files.gains.empty() && files.gains.size() != files.plants.size()) {
      ThrowOption(name, "gains_file",
                  "the links of plant_file (" + std::to_string(files.plants.size()) + ")",
                  std::to_string(files.gains.size()) + " links");
    }
    files.links = static_cast<int>(files.plants.size());
  }
  return files;
}

OptionTable<BodeCommand> MakeBodeOptions() {
  OptionTable<BodeCommand> table("bode", "Frequency response and margins of one link's open loop");
  OptionInfo controller{"controller", "", "", "The controller C of L = C P"};
  controller.choices = {kPid, kFractional, kFractionalEq15, kFractionalOustaloup, kNone};
  controller.required = true;
  table.Add<std::string>(controller, [](BodeCommand& c) -> std::string& { return c.controller; });
  table.Add<std::vector<int>>({"links", "", "distinct links 1..3, or 1..n of plant_file",
                               "Links to analyse (default: every link)"},
                              [](BodeCommand& c) -> std::vector<int>& { return c.links; });
  OptionInfo plant{"plant", "", "", "Link model: g1 (eq. 5) or g2 (eq. 6)"};
  plant.choices = kPlants;
  table.Add<std::string>(plant, [](BodeCommand& c) -> std::string& { return c.plant; });
  AddGainOptions(table);
  table.Add<int>({"oustaloup_pairs", "", "in [1, " + std::to_string(kMaxOustaloupPairs) + "]",
                  "fractional-oustaloup: Oustaloup pairs N"},
                 [](BodeCommand& c) -> int& { return c.oustaloup_n; });
  table.Add<std::vector<double>>({"band_rad_s", "rad/s", "LOW,HIGH with 0 < LOW < HIGH",
                                  "fractional-oustaloup: the realisation's band"},
                                 [](BodeCommand& c) -> std::vector<double>& { return c.band_rad_s; });
  OptionInfo w_min{"w_min_rad_s", "rad/s", "finite and > 0", "bode.csv: lowest frequency"};
  w_min.aliases = {"w_min"};
  table.Add<double>(w_min, [](BodeCommand& c) -> double& { return c.w_min_rad_s; });
  OptionInfo w_max{"w_max_rad_s", "rad/s", "finite and > w_min_rad_s",
                   "bode.csv: highest frequency"};
  w_max.aliases = {"w_max"};
  table.Add<double>(w_max, [](BodeCommand& c) -> double& { return c.w_max_rad_s; });
  table.Add<int>({"points_per_decade", "", "in [1, 100000]", "bode.csv: grid density"},
                 [](BodeCommand& c) -> int& { return c.points_per_decade; });
  AddKeyFileOptions(table);
  OptionInfo out{"out", "", "a folder", "Folder for bode.csv and bode.json (one link)"};
  out.aliases = {"o"};
  table.AddPath(out, [](BodeCommand& c) -> std::string& { return c.out; });
  return table;
}

OptionTable<StepCommand> MakeStepOptions() {
  OptionTable<StepCommand> table(
      "step", "Closed-loop unit step of each link against the reference model");
  OptionInfo controller{"controller", "", "", "The controller: pid (eq. 12) or fractional (eq. 14)"};
  controller.choices = {kPid, kFractional};
  controller.required = true;
  table.Add<std::string>(controller, [](StepCommand& c) -> std::string& { return c.controller; });
  table.Add<std::vector<int>>({"links", "", "distinct links 1..3, or 1..n of plant_file",
                               "Links to simulate (default: every link)"},
                              [](StepCommand& c) -> std::vector<int>& { return c.links; });
  OptionInfo plant{"plant", "", "", "Link model: g1 (eq. 5) or g2 (eq. 6)"};
  plant.choices = kPlants;
  table.Add<std::string>(plant, [](StepCommand& c) -> std::string& { return c.plant; });
  AddGainOptions(table);
  table.Add<double>({"horizon_s", "s", "finite and > 0", "Horizon of step.csv and of J (eq. 11)"},
                    [](StepCommand& c) -> double& { return c.horizon_s; });
  table.Add<double>({"max_horizon_s", "s", "finite and > 0",
                     "Longest record for the step metrics: each link's simulation goes on past "
                     "horizon_s until its metrics are determined"},
                    [](StepCommand& c) -> double& { return c.max_horizon_s; });
  OptionInfo rate{"sample_rate_Hz", "Hz", "finite and > 0", "Controller sample rate"};
  table.Add<double>(rate, [](StepCommand& c) -> double& { return c.sample_rate_Hz; });
  table.Add<bool>({"no_clamp", "", "", "No output clamp (the paper's linear setting)"},
                  [](StepCommand& c) -> bool& { return c.no_clamp; });
  OptionInfo v_max{"v_max_V", "V", "finite and > 0", "Output clamp"};
  v_max.aliases = {"v_max"};
  table.Add<double>(v_max, [](StepCommand& c) -> double& { return c.v_max_V; });
  AddKeyFileOptions(table);
  OptionInfo bench{"bench", "", "a scenario file (TOML) with the links chosen",
                   "Each link's step also on this scenario's simulated multibody strip (its model, "
                   "plants, time step and fluid; the other links held at 0 by their controllers), "
                   "beside the linear loop's, with the same controllers"};
  bench.default_text = "none";
  table.AddPath(bench, [](StepCommand& c) -> std::string& { return c.bench_scenario; });
  OptionInfo out{"out", "", "a folder", "Folder for step.csv and step.json"};
  out.aliases = {"o"};
  table.AddPath(out, [](StepCommand& c) -> std::string& { return c.out; });
  return table;
}

std::string OutFile(const std::string& dir, const char* name) {
  return (std::filesystem::path(dir) / name).string();
}

}  // namespace

const OptionTable<BodeCommand>& BodeOptions() {
  static const OptionTable<BodeCommand> table = MakeBodeOptions();
  return table;
}

const OptionTable<StepCommand>& StepOptions() {
  static const OptionTable<StepCommand> table = MakeStepOptions();
  return table;
}

std::vector<BodeLink> RunBodeCommand(const BodeCommand& command, const OptionGiven& given) {
  const std::string name = BodeOptions().command();
  const KeyFileLinksOf files = ReadKeyFiles(name, command, given);
  const std::vector<int> chosen = files.Chosen(command.links, given);
  ValidateLinkList(name, chosen, files.links);
  if (!command.out.empty() && chosen.size() != 1) {
    ThrowOption(name, "links", "one link with out (bode.csv is one link's)",
                std::to_string(chosen.size()) + " links");
  }
  std::vector<BodeLink> links;
  for (const int link : chosen) {
    BodeSpec spec = command;
    spec.link = link;
    if (!files.plants.empty()) {
      spec.own_plant = files.plants.at(link - 1);
      spec.plant_source = command.plant_file;
    }
    if (!files.gains.empty()) {
      spec.gains = files.gains.at(link - 1);
      spec.gains_source = command.gains_file;
    }
    ValidateBodeSpec(name, spec, given);
    links.push_back({spec, {}, {}});
  }
  for (BodeLink& link : links) {
    link.analysis = AnalyseBode(link.spec);
    link.columns = ComputeBodeColumns(link.analysis, link.spec);
  }
  if (!command.out.empty()) {
    const BodeLink& link = links.front();
    // What the curves are and the loop's margins, for the figure's title,
    // legend and marks.
    const nlohmann::json about = {{"controller", link.spec.controller},
                                  {"controller_description", link.analysis.controller_description},
                                  {"plant", link.spec.plant},
                                  {"plant_description", link.analysis.plant_description},
                                  {"link", link.spec.link},
                                  {"margins", MarginsJson(link.analysis.margins)}};
    EnsureDirectory(command.out);
    WriteFilesTogether({{OutFile(command.out, "bode.csv"), BodeCsv(link.columns)},
                        {OutFile(command.out, "bode.json"), about.dump(2) + "\n"}});
  }
  return links;
}

StepAnalysis RunStepCommand(const StepCommand& command, const OptionGiven& given) {
  const std::string name = StepOptions().command();
  const KeyFileLinksOf files = ReadKeyFiles(name, command, given);
  StepSpec spec = command;
  spec.links = files.Chosen(command.links, given);
  spec.own_plants = files.plants;
  spec.plant_source = command.plant_file;
  spec.link_gains = files.gains;
  spec.gains_source = command.gains_file;
  ValidateStepSpec(name, spec, given);
  if (!command.bench_scenario.empty()) {
    spec.bench = LoadScenario(command.bench_scenario);
    const int bench_links = ScenarioLinkCount(*spec.bench);
    ValidateLinkList(name, spec.links, bench_links);
    if (!spec.link_gains.empty() && static_cast<int>(spec.link_gains.size()) != bench_links) {
      ThrowOption(name, "gains_file",
                  "the links of bench (" + std::to_string(bench_links) + ")",
                  std::to_string(spec.link_gains.size()) + " links");
    }
  }
  StepAnalysis analysis = AnalyseStep(spec);
  if (!command.out.empty()) {
    const nlohmann::json about = {{"controller", command.controller},
                                  {"controller_description", analysis.controller_description},
                                  {"plant", command.plant},
                                  {"clamp_enabled", !command.no_clamp},
                                  {"v_max_V", command.v_max_V}};
    EnsureDirectory(command.out);
    WriteFilesTogether({{OutFile(command.out, "step.csv"), StepCsv(analysis)},
                        {OutFile(command.out, "step.json"), about.dump(2) + "\n"}});
  }
  return analysis;
}

}  // namespace ipmc
