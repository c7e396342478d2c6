#include "sim/cli/analysis_commands.h"

#include "sim/cli/command.h"

#include <complex>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "controllers/linear/frequency_response.h"
#include "sim/io/files.h"
#include "plugin/base/numbers.h"

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

// Gains and bands in descriptions: printf's %g.
std::string Short(double value) { return FormatDouble(value, 6); }

// The options given on the command line.
OptionGiven GivenOn(const CLI::App& command) {
  return [&command](const std::string& option) { return command.count(option) > 0; };
}

// ------------------------------------------------------------------ bode ---

// The margins the bode command prints (the root search of
// controllers/linear/frequency_response.h), null where there is none; the
// Bode figure marks these.
nlohmann::json MarginsJson(const StabilityMargins& margins) {
  const auto number = [](const std::optional<double>& value) {
    return value ? nlohmann::json(*value) : nlohmann::json();
  };
  return {{"gain_crossover_rad_s", number(margins.gain_crossover_rad_s)},
          {"phase_margin_deg", number(margins.phase_margin_deg)},
          {"phase_crossover_rad_s", number(margins.phase_crossover_rad_s)},
          {"gain_margin_db", number(margins.gain_margin_db)}};
}

// bode.csv and bode.json (what the curves are and the loop's margins, for
// the figure's title, legend and marks) of one link.
void WriteBodeFiles(const BodeArgs& args, const BodeSpec& spec, const BodeAnalysis& analysis) {
  const std::string csv = BodeCsv(ComputeBodeColumns(analysis, spec));
  const nlohmann::json about = {{"controller", spec.controller},
                                {"controller_description", analysis.controller_description},
                                {"plant", spec.plant},
                                {"plant_description", analysis.plant_description},
                                {"link", spec.link},
                                {"margins", MarginsJson(analysis.margins)}};
  EnsureDirectory(args.out_dir);
  const std::filesystem::path dir(args.out_dir);
  WriteFilesTogether({{(dir / "bode.csv").string(), csv},
                      {(dir / "bode.json").string(), about.dump(2) + "\n"}});
}

void PrintBode(const BodeSpec& spec, const BodeAnalysis& analysis) {
  const StabilityMargins& margins = analysis.margins;
  std::printf("link %d: open loop L = C x P, controller %s, plant %s (exact fractional response)\n",
              spec.link, spec.controller.c_str(), spec.plant.c_str());
  std::printf("  %s\n  %s\n", analysis.controller_description.c_str(),
              analysis.plant_description.c_str());
  std::printf("margins searched over [%g, %g] rad/s:\n", analysis.search.grid.w_low_rad_s,
              analysis.search.grid.w_high_rad_s);
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
  const Complex c5 = analysis.controller_at_design;
  const Complex p5 = analysis.plant_at_design;
  std::printf("at %g rad/s: controller %.2f dB, %.2f deg; plant %.2f dB, %.2f deg; "
              "open loop %.2f dB, %.2f deg\n",
              analysis.design_frequency_rad_s, MagnitudeDb(c5), PhaseDeg(c5), MagnitudeDb(p5),
              PhaseDeg(p5), MagnitudeDb(c5 * p5), PhaseDeg(c5 * p5));
}

// Every link is checked before the first is analysed.
int RunBode(const CLI::App& command, const BodeArgs& args) {
  const std::string name = command.get_name();
  ValidateLinkList(name, args.links);
  if (!args.out_dir.empty() && args.links.size() != 1) {
    throw std::invalid_argument(name + ": --out writes one link's bode.csv: give one link with "
                                "--links (got " + std::to_string(args.links.size()) + " links)");
  }
  std::vector<BodeSpec> specs;
  for (const int link : args.links) {
    BodeSpec spec = args;
    spec.link = link;
    ValidateBodeSpec(name, spec, GivenOn(command));
    specs.push_back(spec);
  }
  for (const BodeSpec& spec : specs) {
    if (&spec != &specs.front()) std::printf("\n");
    const BodeAnalysis analysis = AnalyseBode(spec);
    if (!args.out_dir.empty()) WriteBodeFiles(args, spec, analysis);
    PrintBode(spec, analysis);
  }
  return 0;
}

// ------------------------------------------------------------------ step ---

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

int RunStep(const CLI::App& command, const StepArgs& args) {
  ValidateStepSpec(command.get_name(), args, GivenOn(command));
  const StepAnalysis analysis = AnalyseStep(args);

  if (!args.out_dir.empty()) {
    const std::string csv = StepCsv(analysis);
    EnsureDirectory(args.out_dir);
    WriteFileAtomically((std::filesystem::path(args.out_dir) / "step.csv").string(), csv);
    const nlohmann::json about = {{"controller", args.controller},
                                  {"controller_description", analysis.controller_description},
                                  {"plant", args.plant},
                                  {"clamp_enabled", !args.no_clamp},
                                  {"v_max_V", args.v_max}};
    WriteFileAtomically((std::filesystem::path(args.out_dir) / "step.json").string(),
                        about.dump(2) + "\n");
  }

  std::printf("unit step (1 mm), controller %s: %s\n", args.controller.c_str(),
              analysis.controller_description.c_str());
  std::printf("  sampled at %g Hz, %s; horizon %g s (step.csv, J_eq11)\n", args.sample_rate_hz,
              args.no_clamp ? "no clamp" : ("clamp +-" + Short(args.v_max) + " V").c_str(),
              args.horizon_s);
  std::printf("  plant s^-0.5 %s (Table 2)", args.plant == "g2" ? "G2" : "G1");
  std::printf("; s^-0.5%s by %d Oustaloup pairs on [%g, %g] rad/s\n",
              args.controller == kFractional ? " and s^-lambda" : "", analysis.oustaloup_pairs,
              analysis.band_low_rad_s, analysis.band_high_rad_s);
  std::printf("%4s %11s %11s %9s %11s %12s %11s %9s %9s\n", "link", "overshoot_%",
              "rise_time_s", "peak_mm", "peak_time_s", "settling_s", "max_abs_u_V", "J_eq11",
              "record_s");
  std::vector<std::string> open_metrics;
  for (const LinkStep& step : analysis.links) {
    char u_text[32], cost_text[32], record_text[32];
    std::snprintf(u_text, sizeof(u_text), "%.3f", step.max_abs_control_V);
    std::snprintf(cost_text, sizeof(cost_text), "%.4f", step.cost);
    std::snprintf(record_text, sizeof(record_text), "%g", step.response.time_s.back());
    PrintStepRow(std::to_string(step.link), step.metrics, step.status, u_text, cost_text,
                 record_text);
    if (step.status != StepRecordStatus::kDetermined) {
      open_metrics.push_back("link " + std::to_string(step.link) + ": " +
                             StepRecordStatusText(step.status) + " at " + record_text + " s");
    }
  }
  char reference_record[32];
  std::snprintf(reference_record, sizeof(reference_record), "%g", analysis.time_s.back());
  PrintStepRow("ref", analysis.reference_metrics, StepRecordStatus::kDetermined, "-", "-",
               reference_record);
  std::printf("ref: reference model 1 / ((s/5)^1.16 + 1) (eq. 9); J_eq11: eq. 11 over the "
              "%g s horizon; settling: %g %% band\n",
              args.horizon_s, 100 * analysis.settling_band);
  std::printf("metrics from each link's record (record_s), simulated past the horizon until "
              "they are determined, at most %g s\n",
              analysis.metrics_horizon_s);
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
  bode->add_option("--links", b.links, "Links to analyse, e.g. 3 or 1,2,3 (Table 2)")
      ->delimiter(',');
  AddPlantOption(bode, b.plant);
  AddGainOptions(bode, b.gains);
  bode->add_option("--oustaloup-pairs", b.oustaloup_n, "fractional-oustaloup: Oustaloup pairs N");
  bode->add_option("--band-rad-s", b.band_rad_s, "fractional-oustaloup: band LOW,HIGH [rad/s]")
      ->delimiter(',');
  bode->add_option("--w-min", b.w_min_rad_s, "bode.csv: lowest frequency [rad/s]");
  bode->add_option("--w-max", b.w_max_rad_s, "bode.csv: highest frequency [rad/s]");
  bode->add_option("--points-per-decade", b.points_per_decade, "bode.csv: grid density");
  bode->add_option("-o,--out", b.out_dir, "Directory for bode.csv and bode.json (one link)");

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
  step->add_option("-o,--out", s.out_dir, "Directory for step.csv");
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
