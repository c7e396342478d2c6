#include "sim/identify/loop_analysis.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "controllers/fractional_integrator.h"
#include "controllers/linear/oustaloup.h"
#include "controllers/linear/state_space.h"
#include "controllers/paper_eq15.h"
#include "controllers/pid.h"
#include "controllers/reference_model.h"
#include "plugin/actuators/ipmc_link_model.h"
#include "plugin/base/numbers.h"
#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/io/files.h"

namespace ipmc {
namespace {

using Complex = std::complex<double>;

constexpr char kPid[] = "pid";
constexpr char kFractional[] = "fractional";
constexpr char kFractionalEq15[] = "fractional-eq15";
constexpr char kFractionalOustaloup[] = "fractional-oustaloup";

// The controllers are compared at the reference model's crossover.
constexpr double kDesignFrequency_rad_s = 5.0;

// Time-domain realisation of s^-0.5 (plant) and s^-lambda (fractional
// controller): two Oustaloup pairs per decade over ten decades, so the
// approximation is far below the other errors over any horizon of interest
// (1/w_b = 1e5 s).
constexpr int kAccurateOustaloupPairs = 20;
constexpr double kAccurateBandLow_rad_s = 1e-5;
constexpr double kAccurateBandHigh_rad_s = 1e5;

constexpr double kSettlingBand = 0.02;
// Samples per link in a step run (memory: three doubles per sample).
constexpr double kMaxStepSamples = 1e6;

// Gains and bands in descriptions: printf's %g.
std::string Short(double value) { return FormatDouble(value, 6); }

[[noreturn]] void ThrowOption(const std::string& command, const std::string& option,
                              const std::string& requirement, const std::string& got) {
  throw std::invalid_argument(command + ": " + option + " must be " + requirement + ", got " +
                              got);
}

void RequireFinitePositive(const std::string& command, const std::string& option,
                           double value) {
  if (!std::isfinite(value) || !(value > 0)) {
    ThrowOption(command, option, "finite and > 0", FormatDouble(value));
  }
}

void RequireLink(const std::string& command, const std::string& option, int link) {
  if (link < 1 || link > 3) ThrowOption(command, option, "1, 2 or 3", std::to_string(link));
}

}  // namespace

void ValidateLinkList(const std::string& command, const std::vector<int>& links) {
  if (links.empty()) ThrowOption(command, "--links", "a list of links 1..3", "none");
  for (std::size_t i = 0; i < links.size(); ++i) {
    RequireLink(command, "--links", links[i]);
    if (std::count(links.begin(), links.begin() + i, links[i]) > 0) {
      ThrowOption(command, "--links", "distinct", "link " + std::to_string(links[i]) + " twice");
    }
  }
}

namespace {

void RequirePlant(const std::string& command, const std::string& plant) {
  if (plant != "g1" && plant != "g2") ThrowOption(command, "--plant", "g1 or g2", plant);
}

// Rejects an option the chosen controller does not take, so that a gain
// given to the wrong controller is not silently ignored.
void RejectIfGiven(const std::string& command, const OptionGiven& given,
                   const std::string& option, bool applies, const std::string& controller) {
  if (!applies && given && given(option)) {
    throw std::invalid_argument(command + ": " + option + " does not apply to --controller " +
                                controller);
  }
}

void ValidatePidGains(const std::string& command, const ControllerGains& gains) {
  const std::pair<const char*, double> terms[] = {
      {"--kp", gains.kp}, {"--ki", gains.ki}, {"--kd", gains.kd}};
  for (const auto& [option, value] : terms) {
    if (!std::isfinite(value) || value < 0) {
      ThrowOption(command, option, "finite and >= 0", FormatDouble(value));
    }
  }
  if (gains.kp == 0 && gains.ki == 0 && gains.kd == 0) {
    throw std::invalid_argument(command + ": at least one of --kp, --ki, --kd must be > 0");
  }
}

void ValidateFractionalGains(const std::string& command, const ControllerGains& gains) {
  RequireFinitePositive(command, "--gain", gains.gain);
  if (!std::isfinite(gains.order) || !(gains.order > 0) || gains.order > 1) {
    ThrowOption(command, "--order", "in (0, 1]", FormatDouble(gains.order));
  }
}

IpmcModelKind PlantKind(const std::string& plant) {
  return plant == "g2" ? IpmcModelKind::kG2 : IpmcModelKind::kG1;
}

std::string PlantDescription(const std::string& plant, int link) {
  const IpmcLinkParams p = PaperLinkParams(link, PlantKind(plant));
  std::ostringstream text;
  text << "P(s) = s^-0.5 ";
  if (p.kind == IpmcModelKind::kG1) {
    text << "G1(s), G1 = " << Short(p.a0_mm_per_V) << " / (" << Short(p.b2_s2) << " s^2 + "
         << Short(p.b1) << " s + 1)";
    if (link == 3) text << " (eq. 7)";
  } else {
    text << "G2(s), G2 = " << Short(p.a0_mm_per_V) << " / (" << Short(p.b1) << " s^"
         << Short(p.alpha) << " + 1)";
  }
  text << " [mm/V], link " << link;
  return text.str();
}

PidController::Config PidConfig(const ControllerGains& gains) {
  PidController::Config config;
  config.kp = gains.kp;
  config.ki = gains.ki;
  config.kd = gains.kd;
  return config;
}

std::string PidDescription(const ControllerGains& gains) {
  return "C(s) = " + Short(gains.kp) + " + " + Short(gains.ki) + "/s + " + Short(gains.kd) + " s";
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
            PidDescription(spec.gains) + " (eq. 10, ideal derivative)"};
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
              FractionalDescription(spec.gains) + " (eq. 13, exact)"};
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

// How far a link's record may be extended for its metrics: --max-horizon-s
// within the sample budget, and never short of the horizon.
double MetricsHorizon_s(const StepSpec& spec) {
  const double budget_s = kMaxStepSamples / spec.sample_rate_hz;
  return std::max(spec.horizon_s, std::min(spec.max_horizon_s, budget_s));
}

StateSpace AccurateLinkPlant(const std::string& plant, int link) {
  IpmcLinkParams params = PaperLinkParams(link, PlantKind(plant));
  params.integrator.w_low_rad_s = kAccurateBandLow_rad_s;
  params.integrator.w_high_rad_s = kAccurateBandHigh_rad_s;
  params.integrator.n = kAccurateOustaloupPairs;
  return LinkStateSpace(params);
}

ClosedLoopResponse SimulateLink(const StepSpec& spec, int link) {
  const StateSpace plant = AccurateLinkPlant(spec.plant, link);
  StepSimulation simulation;
  simulation.horizon_s = spec.horizon_s;
  simulation.max_horizon_s = MetricsHorizon_s(spec);
  simulation.settling_band = kSettlingBand;
  const double sample_period_s = 1.0 / spec.sample_rate_hz;
  if (spec.controller == kPid) {
    PidController::Config config = PidConfig(spec.gains);
    config.sample_period_s = sample_period_s;
    config.clamp_enabled = !spec.no_clamp;
    config.v_max = spec.v_max;
    PidController pid(config);
    return SimulateClosedLoopStep(plant, pid, simulation);
  }
  FractionalIntegrator::Config config;
  config.gain = spec.gains.gain;
  config.order = spec.gains.order;
  config.oustaloup_n = kAccurateOustaloupPairs;
  config.w_low_rad_s = kAccurateBandLow_rad_s;
  config.w_high_rad_s = kAccurateBandHigh_rad_s;
  config.sample_period_s = sample_period_s;
  config.clamp_enabled = !spec.no_clamp;
  config.v_max = spec.v_max;
  FractionalIntegrator integrator(config);
  return SimulateClosedLoopStep(plant, integrator, simulation);
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

}  // namespace

// ------------------------------------------------------------------ bode ---

void ValidateBodeSpec(const std::string& command, const BodeSpec& spec, const OptionGiven& given) {
  const std::string& name = command;
  const std::string& c = spec.controller;
  const bool known = c == kPid || c == kFractional || c == kFractionalEq15 ||
                     c == kFractionalOustaloup || c == "none";
  if (!known) {
    ThrowOption(name, "--controller",
                "pid, fractional, fractional-eq15, fractional-oustaloup or none", "'" + c + "'");
  }
  RequireLink(name, "--links", spec.link);
  RequirePlant(name, spec.plant);
  RejectIfGiven(name, given, "--kp", c == kPid, c);
  RejectIfGiven(name, given, "--ki", c == kPid, c);
  RejectIfGiven(name, given, "--kd", c == kPid, c);
  const bool fractional = c == kFractional || c == kFractionalOustaloup;
  RejectIfGiven(name, given, "--gain", fractional, c);
  RejectIfGiven(name, given, "--order", fractional, c);
  RejectIfGiven(name, given, "--oustaloup-pairs", c == kFractionalOustaloup, c);
  RejectIfGiven(name, given, "--band-rad-s", c == kFractionalOustaloup, c);
  if (c == kPid) ValidatePidGains(name, spec.gains);
  if (fractional) ValidateFractionalGains(name, spec.gains);
  if (spec.oustaloup_n < 1 || spec.oustaloup_n > kMaxOustaloupPairs) {
    ThrowOption(name, "--oustaloup-pairs", "in [1, " + std::to_string(kMaxOustaloupPairs) + "]",
                std::to_string(spec.oustaloup_n));
  }
  if (spec.band_rad_s.size() != 2) {
    const std::size_t count = spec.band_rad_s.size();
    ThrowOption(name, "--band-rad-s", "two frequencies LOW,HIGH",
                std::to_string(count) + (count == 1 ? " value" : " values"));
  }
  RequireFinitePositive(name, "--band-rad-s (low)", spec.band_rad_s[0]);
  if (!std::isfinite(spec.band_rad_s[1]) || !(spec.band_rad_s[1] > spec.band_rad_s[0])) {
    ThrowOption(name, "--band-rad-s (high)", "finite and > the low end",
                FormatDouble(spec.band_rad_s[1]));
  }
  RequireFinitePositive(name, "--w-min", spec.w_min_rad_s);
  if (!std::isfinite(spec.w_max_rad_s) || !(spec.w_max_rad_s > spec.w_min_rad_s)) {
    ThrowOption(name, "--w-max", "finite and > --w-min (" + FormatDouble(spec.w_min_rad_s) + ")",
                FormatDouble(spec.w_max_rad_s));
  }
  if (spec.points_per_decade < 1 || spec.points_per_decade > 100000) {
    ThrowOption(name, "--points-per-decade", "in [1, 100000]",
                std::to_string(spec.points_per_decade));
  }
}

BodeAnalysis AnalyseBode(const BodeSpec& spec) {
  BodeAnalysis analysis;
  const IpmcLinkParams params = PaperLinkParams(spec.link, PlantKind(spec.plant));
  analysis.plant = [params](double w) { return LinkResponseExact(params, w); };
  ControllerResponse controller = BodeController(spec);
  analysis.controller = controller.response;
  analysis.controller_description = std::move(controller.description);
  analysis.plant_description = PlantDescription(spec.plant, spec.link);
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
  if (bode.magnitude_db.size() != n || bode.phase_deg.size() != n) {
    throw std::invalid_argument(
        "WriteBodeCsv: w_rad_s, magnitude_db and phase_deg must have equal "
        "lengths, got " +
        std::to_string(n) + ", " + std::to_string(bode.magnitude_db.size()) +
        ", " + std::to_string(bode.phase_deg.size()));
  }
  CsvWriter csv;
  csv.Row({columns::kFrequency, columns::kMagnitudeDb, columns::kPhaseDeg});
  for (std::size_t i = 0; i < n; ++i) {
    csv.Add(bode.w_rad_s[i]).Add(bode.magnitude_db[i]).Add(bode.phase_deg[i]).EndRow();
  }
  WriteFileAtomically(path.string(), csv.Text());
}

std::string BodeCsv(const BodeColumns& bode) {
  const BodeData* columns[] = {&bode.plant, &bode.controller, &bode.open_loop,
                               &bode.reference_open_loop};
  std::ostringstream csv;
  csv << std::setprecision(12);
  csv << "w_rad_s,plant_db,plant_deg,controller_db,controller_deg,open_loop_db,open_loop_deg,"
         "reference_open_loop_db,reference_open_loop_deg\n";
  for (std::size_t i = 0; i < bode.plant.w_rad_s.size(); ++i) {
    csv << bode.plant.w_rad_s[i];
    for (const BodeData* column : columns) {
      csv << "," << column->magnitude_db[i] << "," << column->phase_deg[i];
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
    ThrowOption(name, "--controller", "pid or fractional", "'" + c + "'");
  }
  RequirePlant(name, spec.plant);
  RejectIfGiven(name, given, "--kp", c == kPid, c);
  RejectIfGiven(name, given, "--ki", c == kPid, c);
  RejectIfGiven(name, given, "--kd", c == kPid, c);
  RejectIfGiven(name, given, "--gain", c == kFractional, c);
  RejectIfGiven(name, given, "--order", c == kFractional, c);
  if (spec.no_clamp && given && given("--v-max")) {
    throw std::invalid_argument(name + ": --v-max does not apply with --no-clamp");
  }
  if (c == kPid) ValidatePidGains(name, spec.gains);
  if (c == kFractional) ValidateFractionalGains(name, spec.gains);
  ValidateLinkList(name, spec.links);
  RequireFinitePositive(name, "--horizon-s", spec.horizon_s);
  RequireFinitePositive(name, "--sample-rate-hz", spec.sample_rate_hz);
  if (spec.horizon_s * spec.sample_rate_hz > kMaxStepSamples) {
    throw std::invalid_argument(name + ": --horizon-s x --sample-rate-hz must be at most " +
                                Short(kMaxStepSamples) + " samples, got " +
                                FormatDouble(spec.horizon_s * spec.sample_rate_hz));
  }
  if (!spec.no_clamp) RequireFinitePositive(name, "--v-max", spec.v_max);
  RequireFinitePositive(name, "--max-horizon-s", spec.max_horizon_s);
}

StepAnalysis AnalyseStep(const StepSpec& spec) {
  const ReferenceModel model;
  StepAnalysis analysis;
  analysis.settling_band = kSettlingBand;
  analysis.oustaloup_pairs = kAccurateOustaloupPairs;
  analysis.band_low_rad_s = kAccurateBandLow_rad_s;
  analysis.band_high_rad_s = kAccurateBandHigh_rad_s;
  analysis.metrics_horizon_s = MetricsHorizon_s(spec);
  analysis.controller_description = spec.controller == kPid
                                        ? PidDescription(spec.gains) + " (eq. 10)"
                                        : FractionalDescription(spec.gains) + " (eq. 13)";
  for (int link : spec.links) {
    LinkStep step;
    step.link = link;
    step.response = SimulateLink(spec, link);
    step.metrics = ComputeStepMetrics(step.response, kSettlingBand);
    step.status = CheckStepRecord(step.response, kSettlingBand);
    for (double u : step.response.control) {
      step.max_abs_control_V = std::max(step.max_abs_control_V, std::abs(u));
    }
    step.cost = ReferenceModelCost(step.response, model, spec.horizon_s);
    analysis.links.push_back(std::move(step));
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

}  // namespace ipmc
