#include "sim/cli/analysis_commands.h"

#include "sim/cli/command.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/io/error.h"
#include "sim/io/files.h"
#include "controllers/closed_loop.h"
#include "sim/io/numbers.h"
#include "controllers/fractional_integrator.h"
#include "controllers/linear/frequency_response.h"
#include "controllers/linear/oustaloup.h"
#include "controllers/paper_eq15.h"
#include "controllers/pid.h"
#include "controllers/reference_model.h"
#include "controllers/linear/state_space.h"
#include "plugin/actuators/ipmc_link_model.h"
#include "sim/identify/controller_design.h"
#include "sim/runs/output.h"

namespace ipmc {
namespace {

using Complex = std::complex<double>;

constexpr char kBodeCommand[] = "bode";
constexpr char kStepCommand[] = "step";

constexpr char kPid[] = "pid";
constexpr char kFractional[] = "fractional";
constexpr char kFractionalEq15[] = "fractional-eq15";
constexpr char kFractionalOustaloup[] = "fractional-oustaloup";
constexpr char kNone[] = "none";

// The controllers are compared at the reference model's crossover.
constexpr double kDesignFrequency_rad_s = 5.0;

constexpr double kSettlingBand = 0.02;
// bode.csv and step.csv: 12 significant digits.
constexpr int kCsvDigits = 12;
// Samples per link in a step run (memory: three doubles per sample).
constexpr double kMaxStepSamples = 1e6;

// Gains and bands in descriptions: printf's %g.
std::string Short(double value) { return FormatDouble(value, 6); }

void RequireLink(const std::string& command, const std::string& option, int link) {
  if (link < 1 || link > 3) ThrowOption(command, option, "1, 2 or 3", std::to_string(link));
}

// Rejects an option the chosen controller does not take, so that a gain
// given to the wrong controller is not silently ignored.
void RejectIfGiven(const CLI::App& command, const std::string& option, bool applies,
                   const std::string& controller) {
  if (!applies && command.count(option) > 0) {
    throw std::invalid_argument(command.get_name() + ": " + option +
                                " does not apply to --controller " + controller);
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

// ------------------------------------------------------------------ bode ---

struct ControllerResponse {
  FrequencyFunction response;
  std::string description;
};

ControllerResponse BodeController(const BodeArgs& args) {
  const std::string& c = args.controller;
  if (c == kPid) {
    const PidController pid(PidConfig(args.gains));
    return {[pid](double w) { return pid.Evaluate({0.0, w}); },
            PidDescription(args.gains) + " (eq. 10, ideal derivative)"};
  }
  if (c == kFractional || c == kFractionalOustaloup) {
    FractionalIntegrator::Config config;
    config.gain = args.gains.gain;
    config.order = args.gains.order;
    config.oustaloup_n = args.oustaloup_n;
    config.w_low_rad_s = args.band_rad_s[0];
    config.w_high_rad_s = args.band_rad_s[1];
    const FractionalIntegrator integrator(config);
    if (c == kFractional) {
      return {[integrator](double w) { return integrator.EvaluateExact({0.0, w}); },
              FractionalDescription(args.gains) + " (eq. 13, exact)"};
    }
    return {[integrator](double w) { return integrator.Evaluate({0.0, w}); },
            FractionalDescription(args.gains) + " by Oustaloup, " +
                std::to_string(args.oustaloup_n) + " pairs on [" + Short(args.band_rad_s[0]) +
                ", " + Short(args.band_rad_s[1]) + "] rad/s"};
  }
  if (c == kFractionalEq15) {
    return {[](double w) { return Eq15Evaluate({0.0, w}); }, Eq15Description()};
  }
  return {[](double) { return Complex(1.0, 0.0); }, "C(s) = 1 (no controller)"};
}

void ValidateBode(const CLI::App& command, const BodeArgs& args) {
  const std::string name = command.get_name();
  const std::string& c = args.controller;
  RequireLink(name, "--link", args.link);
  RejectIfGiven(command, "--kp", c == kPid, c);
  RejectIfGiven(command, "--ki", c == kPid, c);
  RejectIfGiven(command, "--kd", c == kPid, c);
  const bool fractional = c == kFractional || c == kFractionalOustaloup;
  RejectIfGiven(command, "--gain", fractional, c);
  RejectIfGiven(command, "--order", fractional, c);
  RejectIfGiven(command, "--n", c == kFractionalOustaloup, c);
  RejectIfGiven(command, "--band-rad-s", c == kFractionalOustaloup, c);
  if (c == kPid) ValidatePidGains(name, args.gains);
  if (fractional) ValidateFractionalGains(name, args.gains);
  if (args.oustaloup_n < 1 || args.oustaloup_n > kMaxOustaloupPairs) {
    ThrowOption(name, "--n", "in [1, " + std::to_string(kMaxOustaloupPairs) + "]",
                std::to_string(args.oustaloup_n));
  }
  if (args.band_rad_s.size() != 2) {
    const std::size_t count = args.band_rad_s.size();
    ThrowOption(name, "--band-rad-s", "two frequencies LOW,HIGH",
                std::to_string(count) + (count == 1 ? " value" : " values"));
  }
  RequireFinitePositive(name, "--band-rad-s (low)", args.band_rad_s[0]);
  if (!std::isfinite(args.band_rad_s[1]) || !(args.band_rad_s[1] > args.band_rad_s[0])) {
    ThrowOption(name, "--band-rad-s (high)", "finite and > the low end",
                FormatDouble(args.band_rad_s[1]));
  }
  RequireFinitePositive(name, "--w-min", args.w_min_rad_s);
  if (!std::isfinite(args.w_max_rad_s) || !(args.w_max_rad_s > args.w_min_rad_s)) {
    ThrowOption(name, "--w-max", "finite and > --w-min (" + FormatDouble(args.w_min_rad_s) + ")",
                FormatDouble(args.w_max_rad_s));
  }
  if (args.points_per_decade < 1 || args.points_per_decade > 100000) {
    ThrowOption(name, "--points-per-decade", "in [1, 100000]",
                std::to_string(args.points_per_decade));
  }
}

std::string BodeCsv(const FrequencyFunction& plant, const FrequencyFunction& controller,
                    const FrequencyFunction& loop, const FrequencyGrid& grid) {
  const ReferenceModel model;
  const BodeData curves[] = {
      ComputeBode(plant, grid), ComputeBode(controller, grid), ComputeBode(loop, grid),
      ComputeBode([&model](double w) { return model.OpenLoop({0.0, w}); }, grid)};
  const char* names[] = {columns::kPlantCurve, columns::kControllerCurve,
                         columns::kOpenLoopCurve, columns::kReferenceOpenLoopCurve};
  CsvWriter csv(kCsvDigits);
  csv.Add(columns::kFrequency);
  for (const char* name : names) csv.Add(columns::MagnitudeDb(name)).Add(columns::PhaseDeg(name));
  csv.EndRow();
  for (std::size_t i = 0; i < curves[0].w_rad_s.size(); ++i) {
    csv.Add(curves[0].w_rad_s[i]);
    for (const BodeData& curve : curves) csv.Add(curve.magnitude_db[i]).Add(curve.phase_deg[i]);
    csv.EndRow();
  }
  return csv.Text();
}

int RunBode(const CLI::App& command, const BodeArgs& args) {
  ValidateBode(command, args);
  const IpmcLinkParams params = PaperLinkParams(args.link, PlantKind(args.plant));
  const FrequencyFunction plant = [params](double w) { return LinkResponseExact(params, w); };
  const ControllerResponse controller = BodeController(args);
  const FrequencyFunction loop = [plant, c = controller.response](double w) {
    return c(w) * plant(w);
  };
  const MarginSearch search;
  const StabilityMargins margins = ComputeMargins(loop, search);

  if (!args.out_dir.empty()) {
    FrequencyGrid grid;
    grid.w_low_rad_s = args.w_min_rad_s;
    grid.w_high_rad_s = args.w_max_rad_s;
    grid.points_per_decade = args.points_per_decade;
    const std::string csv = BodeCsv(plant, controller.response, loop, grid);
    EnsureDirectory(args.out_dir);
    WriteFileAtomically((std::filesystem::path(args.out_dir) / "bode.csv").string(), csv);
  }

  std::printf("open loop L = C x P, controller %s, plant %s (exact fractional response)\n",
              args.controller.c_str(), args.plant.c_str());
  std::printf("  %s\n  %s\n", controller.description.c_str(),
              PlantDescription(args.plant, args.link).c_str());
  std::printf("margins searched over [%g, %g] rad/s:\n", search.grid.w_low_rad_s,
              search.grid.w_high_rad_s);
  if (margins.gain_crossover_rad_s) {
    std::printf("gain crossover: %.3f rad/s\n", *margins.gain_crossover_rad_s);
    std::printf("phase margin: %.2f deg\n", *margins.phase_margin_deg);
    if (margins.gain_crossovers_rad_s.size() > 1) {
      std::printf("  (%zu gain crossovers; the lowest is reported)\n",
                  margins.gain_crossovers_rad_s.size());
    }
  } else {
    std::printf("gain crossover: none (|L| does not cross 1)\n");
  }
  if (margins.gain_margin_db) {
    std::printf("gain margin: %.2f dB at %.3f rad/s\n", *margins.gain_margin_db,
                *margins.phase_crossover_rad_s);
  } else {
    std::printf("gain margin: no finite gain margin (the phase does not reach -180 deg)\n");
  }
  const Complex c5 = controller.response(kDesignFrequency_rad_s);
  const Complex p5 = plant(kDesignFrequency_rad_s);
  std::printf("at %g rad/s: controller %.2f dB, %.2f deg; plant %.2f dB, %.2f deg; "
              "open loop %.2f dB, %.2f deg\n",
              kDesignFrequency_rad_s, MagnitudeDb(c5), PhaseDeg(c5), MagnitudeDb(p5),
              PhaseDeg(p5), MagnitudeDb(c5 * p5), PhaseDeg(c5 * p5));
  return 0;
}

// ------------------------------------------------------------------ step ---

void ValidateStep(const CLI::App& command, const StepArgs& args) {
  const std::string name = command.get_name();
  const std::string& c = args.controller;
  RejectIfGiven(command, "--kp", c == kPid, c);
  RejectIfGiven(command, "--ki", c == kPid, c);
  RejectIfGiven(command, "--kd", c == kPid, c);
  RejectIfGiven(command, "--gain", c == kFractional, c);
  RejectIfGiven(command, "--order", c == kFractional, c);
  if (args.no_clamp && command.count("--v-max") > 0) {
    throw std::invalid_argument(name + ": --v-max does not apply with --no-clamp");
  }
  if (c == kPid) ValidatePidGains(name, args.gains);
  if (c == kFractional) ValidateFractionalGains(name, args.gains);
  if (args.links.empty()) ThrowOption(name, "--links", "a list of links 1..3", "none");
  for (std::size_t i = 0; i < args.links.size(); ++i) {
    RequireLink(name, "--links", args.links[i]);
    if (std::count(args.links.begin(), args.links.begin() + i, args.links[i]) > 0) {
      ThrowOption(name, "--links", "distinct", "link " + std::to_string(args.links[i]) + " twice");
    }
  }
  RequireFinitePositive(name, "--horizon-s", args.horizon_s);
  RequireFinitePositive(name, "--sample-rate-hz", args.sample_rate_hz);
  if (args.horizon_s * args.sample_rate_hz > kMaxStepSamples) {
    throw std::invalid_argument(name + ": --horizon-s x --sample-rate-hz must be at most " +
                                Short(kMaxStepSamples) + " samples, got " +
                                FormatDouble(args.horizon_s * args.sample_rate_hz));
  }
  if (!args.no_clamp) RequireFinitePositive(name, "--v-max", args.v_max);
  RequireFinitePositive(name, "--max-horizon-s", args.max_horizon_s);
}

// How far a link's record may be extended for its metrics: --max-horizon-s
// within the sample budget, and never short of the horizon.
double MetricsHorizon_s(const StepArgs& args) {
  const double budget_s = kMaxStepSamples / args.sample_rate_hz;
  return std::max(args.horizon_s, std::min(args.max_horizon_s, budget_s));
}

ClosedLoopResponse SimulateLink(const StepArgs& args, int link) {
  const StateSpace plant = AccurateLinkPlant(PaperLinkParams(link, PlantKind(args.plant)));
  StepSimulation simulation;
  simulation.horizon_s = args.horizon_s;
  simulation.max_horizon_s = MetricsHorizon_s(args);
  simulation.settling_band = kSettlingBand;
  const double sample_period_s = 1.0 / args.sample_rate_hz;
  if (args.controller == kPid) {
    PidController::Config config = PidConfig(args.gains);
    config.sample_period_s = sample_period_s;
    config.clamp_enabled = !args.no_clamp;
    config.v_max = args.v_max;
    PidController pid(config);
    return SimulateClosedLoopStep(plant, pid, simulation);
  }
  FractionalIntegrator::Config config;
  config.gain = args.gains.gain;
  config.order = args.gains.order;
  config.oustaloup_n = kAccurateOustaloupPairs;
  config.w_low_rad_s = kAccurateBandLow_rad_s;
  config.w_high_rad_s = kAccurateBandHigh_rad_s;
  config.sample_period_s = sample_period_s;
  config.clamp_enabled = !args.no_clamp;
  config.v_max = args.v_max;
  FractionalIntegrator integrator(config);
  return SimulateClosedLoopStep(plant, integrator, simulation);
}

std::string Optional(const std::optional<double>& value, const char* format) {
  if (!value) return "-";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), format, *value);
  return buffer;
}

// One row of the step table. A '*' marks a metric the record does not
// determine: a peak at the end of the record (the response has not
// turned yet, so overshoot and peak are lower bounds), or a settling time
// after half the record (the response may leave the band again).
void PrintStepRow(const std::string& label, const StepMetrics& m, StepRecordStatus status,
                  const std::string& max_abs_u, const std::string& cost,
                  const std::string& record) {
  const bool still_rising = status == StepRecordStatus::kPeakAtEnd;
  const bool settled_late = status == StepRecordStatus::kSettledLate;
  char overshoot[32], peak_time[32];
  std::snprintf(overshoot, sizeof(overshoot), "%.3f%s", m.overshoot_percent,
                still_rising ? "*" : "");
  std::snprintf(peak_time, sizeof(peak_time), "%.4f%s", m.peak_time_s, still_rising ? "*" : "");
  std::string settling = Optional(m.settling_time_s, "%.4f");
  if (settled_late && m.settling_time_s) settling += "*";
  std::printf("%4s %11s %11s %9.5f %11s %12s %11s %9s %9s\n", label.c_str(), overshoot,
              Optional(m.rise_time_s, "%.4f").c_str(), m.peak_value, peak_time, settling.c_str(),
              max_abs_u.c_str(), cost.c_str(), record.c_str());
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

// Rows t = time_s[0 .. reference.size() - 1] (the horizon).
std::string StepCsv(const std::vector<double>& time_s, const std::vector<double>& reference,
                    const std::vector<int>& links,
                    const std::vector<ClosedLoopResponse>& responses) {
  CsvWriter csv(kCsvDigits);
  csv.Add(columns::kTime).Add(columns::kReferenceModel);
  for (int link : links) csv.Add(columns::StepOutput(link));
  for (int link : links) csv.Add(columns::StepVoltage(link));
  csv.EndRow();
  for (std::size_t i = 0; i < reference.size(); ++i) {
    csv.Add(time_s[i]).Add(reference[i]);
    for (const ClosedLoopResponse& r : responses) csv.Add(r.output[i]);
    for (const ClosedLoopResponse& r : responses) csv.Add(r.control[i]);
    csv.EndRow();
  }
  return csv.Text();
}

int RunStep(const CLI::App& command, const StepArgs& args) {
  ValidateStep(command, args);
  const ReferenceModel model;
  std::vector<ClosedLoopResponse> responses;
  for (int link : args.links) responses.push_back(SimulateLink(args, link));

  // The reference model on the horizon's time grid (the links share it;
  // their records may go on past it for their metrics).
  const std::vector<double>& time_s = responses.front().time_s;
  const std::size_t horizon_points =
      HorizonPoints(time_s, args.horizon_s, responses.front().sample_period_s);
  std::vector<double> reference(horizon_points);
  for (std::size_t i = 0; i < horizon_points; ++i) reference[i] = model.StepResponse(time_s[i]);

  if (!args.out_dir.empty()) {
    const std::string csv = StepCsv(time_s, reference, args.links, responses);
    EnsureDirectory(args.out_dir);
    WriteFileAtomically((std::filesystem::path(args.out_dir) / "step.csv").string(), csv);
  }

  const std::string controller = args.controller == kPid
                                     ? PidDescription(args.gains) + " (eq. 10)"
                                     : FractionalDescription(args.gains) + " (eq. 13)";
  const double metrics_horizon_s = MetricsHorizon_s(args);
  std::printf("unit step (1 mm), controller %s: %s\n", args.controller.c_str(),
              controller.c_str());
  std::printf("  sampled at %g Hz, %s; horizon %g s (step.csv, J_eq11)\n", args.sample_rate_hz,
              args.no_clamp ? "no clamp" : ("clamp +-" + Short(args.v_max) + " V").c_str(),
              args.horizon_s);
  std::printf("  plant s^-0.5 %s (Table 2)", args.plant == "g2" ? "G2" : "G1");
  std::printf("; s^-0.5%s by %d Oustaloup pairs on [%g, %g] rad/s\n",
              args.controller == kFractional ? " and s^-lambda" : "", kAccurateOustaloupPairs,
              kAccurateBandLow_rad_s, kAccurateBandHigh_rad_s);
  std::printf("%4s %11s %11s %9s %11s %12s %11s %9s %9s\n", "link", "overshoot_%",
              "rise_time_s", "peak_mm", "peak_time_s", "settling_s", "max_abs_u_V", "J_eq11",
              "record_s");
  std::vector<std::string> open_metrics;
  for (std::size_t k = 0; k < responses.size(); ++k) {
    const ClosedLoopResponse& r = responses[k];
    const StepMetrics metrics = ComputeStepMetrics(r, kSettlingBand);
    const StepRecordStatus status = CheckStepRecord(r, kSettlingBand);
    double max_abs_u = 0;
    for (double u : r.control) max_abs_u = std::max(max_abs_u, std::abs(u));
    const double cost = ReferenceModelCost(r, model, args.horizon_s);
    char u_text[32], cost_text[32], record_text[32];
    std::snprintf(u_text, sizeof(u_text), "%.3f", max_abs_u);
    std::snprintf(cost_text, sizeof(cost_text), "%.4f", cost);
    std::snprintf(record_text, sizeof(record_text), "%g", r.time_s.back());
    PrintStepRow(std::to_string(args.links[k]), metrics, status, u_text, cost_text, record_text);
    if (status != StepRecordStatus::kDetermined) {
      open_metrics.push_back("link " + std::to_string(args.links[k]) + ": " +
                             StepRecordStatusText(status) + " at " + record_text + " s");
    }
  }
  // The reference model: its exact first peak where the horizon holds it.
  const std::vector<double> reference_time_s(time_s.begin(), time_s.begin() + horizon_points);
  StepMetrics reference_metrics =
      ComputeStepMetrics(reference_time_s, reference, 1.0, kSettlingBand);
  const std::optional<ReferenceModel::Peak> peak = model.StepPeak();
  if (peak && peak->time_s <= reference_time_s.back()) {
    reference_metrics.peak_value = peak->value;
    reference_metrics.peak_time_s = peak->time_s;
    reference_metrics.overshoot_percent = 100.0 * (peak->value - 1.0);
  }
  char reference_record[32];
  std::snprintf(reference_record, sizeof(reference_record), "%g", reference_time_s.back());
  PrintStepRow("ref", reference_metrics, StepRecordStatus::kDetermined, "-", "-",
               reference_record);
  std::printf("ref: reference model 1 / ((s/5)^1.16 + 1) (eq. 9); J_eq11: eq. 11 over the "
              "%g s horizon; settling: %g %% band\n",
              args.horizon_s, 100 * kSettlingBand);
  std::printf("metrics from each link's record (record_s), simulated past the horizon until "
              "they are determined, at most %g s\n",
              metrics_horizon_s);
  if (!open_metrics.empty()) {
    std::string list;
    for (const std::string& item : open_metrics) list += (list.empty() ? "" : "; ") + item;
    std::printf("*: not determined by the record (%s); raise --max-horizon-s\n", list.c_str());
  }
  return 0;
}

// --kp, --ki, --kd (PID) and --gain, --order (fractional integrator).
void AddGainOptions(CLI::App* command, ControllerGains& gains) {
  command->add_option("--kp", gains.kp, "PID proportional gain [V/mm]");
  command->add_option("--ki", gains.ki, "PID integral gain [V/(mm s)]");
  command->add_option("--kd", gains.kd, "PID derivative gain [V s/mm]");
  command->add_option("--gain", gains.gain, "Fractional integrator gain K");
  command->add_option("--order", gains.order, "Fractional integrator order lambda, in (0, 1]");
}

}  // namespace

void AddAnalysisCommands(CLI::App& app, AnalysisArgs& args) {
  const std::vector<std::string> bode_controllers = {kPid, kFractional, kFractionalEq15,
                                                     kFractionalOustaloup, kNone};
  BodeArgs& b = args.bode;
  CLI::App* bode =
      AddCommand(app, kBodeCommand, "Frequency response and margins of one link's open loop");
  bode->add_option("--controller", b.controller,
                   "pid (eq. 12) | fractional (eq. 14, exact) | fractional-eq15 | "
                   "fractional-oustaloup | none")
      ->required()->check(CLI::IsMember(bode_controllers));
  bode->add_option("--link", b.link, "Link 1..3 (Table 2)");
  AddPlantOption(bode, b.plant);
  AddGainOptions(bode, b.gains);
  bode->add_option("--n", b.oustaloup_n, "fractional-oustaloup: Oustaloup pairs");
  bode->add_option("--band-rad-s", b.band_rad_s, "fractional-oustaloup: band LOW,HIGH [rad/s]")
      ->delimiter(',');
  bode->add_option("--w-min", b.w_min_rad_s, "bode.csv: lowest frequency [rad/s]");
  bode->add_option("--w-max", b.w_max_rad_s, "bode.csv: highest frequency [rad/s]");
  bode->add_option("--points-per-decade", b.points_per_decade, "bode.csv: grid density");
  bode->add_option("--out", b.out_dir, "Directory for bode.csv");

  StepArgs& s = args.step;
  CLI::App* step =
      AddCommand(app, kStepCommand, "Closed-loop unit step of each link against the reference model");
  step->add_option("--controller", s.controller, "pid (eq. 12) | fractional (eq. 14)")
      ->required()->check(CLI::IsMember({kPid, kFractional}));
  step->add_option("--links", s.links, "Links to simulate, e.g. 1,2,3")
      ->delimiter(',');
  AddPlantOption(step, s.plant);
  AddGainOptions(step, s.gains);
  step->add_option("--horizon-s", s.horizon_s, "Horizon of step.csv and of J (eq. 11) [s]");
  step->add_option("--max-horizon-s", s.max_horizon_s,
                   "Longest record for the step metrics [s]: each link's simulation goes on "
                   "past --horizon-s until its metrics are determined");
  step->add_option("--sample-rate-hz", s.sample_rate_hz, "Controller sample rate [Hz]");
  step->add_flag("--no-clamp", s.no_clamp, "No output clamp (the paper's linear setting)");
  step->add_option("--v-max", s.v_max, "Output clamp [V]");
  step->add_option("--out", s.out_dir, "Directory for step.csv");
}

int RunAnalysisCommand(const CLI::App& app, const AnalysisArgs& args) {
  if (app.got_subcommand(kBodeCommand)) {
    return RunBode(*app.get_subcommand(kBodeCommand), args.bode);
  }
  if (app.got_subcommand(kStepCommand)) {
    return RunStep(*app.get_subcommand(kStepCommand), args.step);
  }
  return -1;
}

}  // namespace ipmc
