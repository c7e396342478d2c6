#include "sim/cli/step_command.h"

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "controllers/controller_names.h"
#include "sim/base/numbers.h"

namespace ipmc {
namespace {

// Gains and bands in descriptions: printf's %g.
std::string Short(double value) { return FormatDouble(value, 6); }

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
                  const std::string& record, const std::string& indices) {
  const bool still_rising = status == StepRecordStatus::kPeakAtEnd;
  const bool settled_late = status == StepRecordStatus::kSettledLate;
  char overshoot[32], peak_time[32];
  std::snprintf(overshoot, sizeof(overshoot), "%.3f%s", m.overshoot_percent,
                still_rising ? "*" : "");
  std::snprintf(peak_time, sizeof(peak_time), "%.4f%s", m.peak_time_s, still_rising ? "*" : "");
  std::string settling = Optional(m.settling_time_s, "%.4f");
  if (settled_late && m.settling_time_s) settling += "*";
  std::printf("%4s %11s %11s %9.5f %11s %12s %11s %9s %9s %s\n", label.c_str(), overshoot,
              Optional(m.rise_time_s, "%.4f").c_str(), m.peak_value, peak_time, settling.c_str(),
              max_abs_u.c_str(), cost.c_str(), record.c_str(), indices.c_str());
}

void PrintStepHeader() {
  std::printf("%4s %11s %11s %9s %11s %12s %11s %9s %9s %10s %11s\n", "link", "overshoot_%",
              "rise_time_s", "peak_mm", "peak_time_s", "settling_s", "max_abs_u_V", "J_eq11",
              "record_s", "iae_mm_s", "itae_mm_s2");
}

// The links' rows; returns what their records leave open, one item a link.
std::vector<std::string> PrintLinkRows(const std::vector<LinkStep>& steps) {
  std::vector<std::string> open_metrics;
  for (const LinkStep& step : steps) {
    char u_text[32], cost_text[32], record_text[32], indices_text[64];
    std::snprintf(u_text, sizeof(u_text), "%.3f", step.max_abs_control_V);
    std::snprintf(cost_text, sizeof(cost_text), "%.4f", step.cost);
    std::snprintf(record_text, sizeof(record_text), "%g", step.response.time_s.back());
    std::snprintf(indices_text, sizeof(indices_text), "%10.6f %11.6f", step.indices.iae_mm_s,
                  step.indices.itae_mm_s2);
    PrintStepRow(std::to_string(step.link), step.metrics, step.status, u_text, cost_text,
                 record_text, indices_text);
    if (step.status != StepRecordStatus::kDetermined) {
      open_metrics.push_back("link " + std::to_string(step.link) + ": " +
                             StepRecordStatusText(step.status) + " at " + record_text + " s");
    }
  }
  return open_metrics;
}

std::string JoinedItems(const std::vector<std::string>& items) {
  std::string list;
  for (const std::string& item : items) list += (list.empty() ? "" : "; ") + item;
  return list;
}

void PrintStep(const StepCommand& args, const StepAnalysis& analysis) {
  std::printf("unit step (1 mm), controller %s: %s\n", args.controller.c_str(),
              analysis.controller_description.c_str());
  std::printf("  sampled at %g Hz, %s; horizon %g s (step.csv, J_eq11)\n", args.sample_rate_Hz,
              args.no_clamp ? "no clamp" : ("clamp +-" + Short(args.v_max_V) + " V").c_str(),
              args.horizon_s);
  if (args.plant_file.empty()) {
    std::printf("  plant s^-0.5 %s (Table 2)", args.plant == "g2" ? "G2" : "G1");
  } else {
    std::printf("  each link's plant from %s", args.plant_file.c_str());
  }
  std::printf("; s^-0.5%s by %d Oustaloup pairs on [%g, %g] rad/s\n",
              args.controller == controller_names::kFractional ? " and s^-lambda" : "", analysis.oustaloup_pairs,
              analysis.band_low_rad_s, analysis.band_high_rad_s);
  PrintStepHeader();
  std::vector<std::string> open_metrics = PrintLinkRows(analysis.links);
  char reference_record[32];
  std::snprintf(reference_record, sizeof(reference_record), "%g", analysis.time_s.back());
  PrintStepRow("ref", analysis.reference_metrics, StepRecordStatus::kDetermined, "-", "-",
               reference_record, "         -           -");
  std::printf("ref: reference model 1 / ((s/5)^1.16 + 1) (eq. 9); J_eq11: eq. 11 over the "
              "%g s horizon; settling: %g %% band\n",
              args.horizon_s, 100 * analysis.settling_band);
  std::printf("iae_mm_s, itae_mm_s2: Table 5's indices of the error 1 mm - y over the horizon "
              "(rectangle rule at the sample rate)\n");
  std::printf("metrics from each link's record (record_s), simulated past the horizon until "
              "they are determined, at most %g s\n",
              analysis.metrics_horizon_s);
  if (!open_metrics.empty()) {
    std::printf("*: not determined by the record (%s); raise --max-horizon-s\n",
                JoinedItems(open_metrics).c_str());
  }
  if (analysis.bench.empty()) return;
  std::printf("\non the multibody bench %s (its model, plants, time step and fluid; the "
              "stepped link's reference 1 mm from t = 0, the other links' 0, every link under "
              "the controllers above), over the %g s horizon:\n",
              args.bench_scenario.c_str(), args.horizon_s);
  PrintStepHeader();
  const std::vector<std::string> open_bench = PrintLinkRows(analysis.bench);
  if (!open_bench.empty()) {
    std::printf("*: not determined by the bench's record (%s); raise --horizon-s\n",
                JoinedItems(open_bench).c_str());
  }
}

}  // namespace

void AddStepCommand(CLI::App& app, StepArgs& args) { AddTableCommand(app, StepOptions(), args); }

int RunStepCommandLine(const StepArgs& args) {
  if (!args.Chosen()) return -1;
  const StepAnalysis analysis = TranslatingFieldErrors(
      StepOptions(), [&] { return RunStepCommand(args.spec, args.Given()); });
  PrintStep(args.spec, analysis);
  return 0;
}

}  // namespace ipmc
