// Bode diagram (Fig. 9, 10) and closed-loop steps (Fig. 11).
#include "renders/figure_parts.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/base/error.h"
#include "sim/base/numbers.h"

namespace ipmc::figure_parts {
namespace {

// ------------------------------------------------------------------ bode ---

// The open loop's margins as the bode command found them by root search on
// the exact response (sim/linear/frequency_response.h) and wrote
// them to bode.json; empty where there is none or no bode.json.
struct Margins {
  bool known = false;  // bode.json holds them
  std::optional<double> crossover_rad_s, phase_margin_deg;
  std::optional<double> phase_crossover_rad_s, gain_margin_dB;
};

Margins MarginsOf(const nlohmann::json& about) {
  const nlohmann::json margins =
      about.is_object() ? about.value("margins", nlohmann::json()) : nlohmann::json();
  const auto number = [&](const char* key) -> std::optional<double> {
    if (!margins.is_object() || !margins.contains(key) || !margins[key].is_number()) return {};
    return margins[key].get<double>();
  };
  return {margins.is_object(), number("gain_crossover_rad_s"), number("phase_margin_deg"),
          number("phase_crossover_rad_s"), number("gain_margin_dB")};
}

std::string BodeLabel(const std::string& curve, const nlohmann::json& about) {
  const std::string controller = JsonText(about, "controller");
  const std::string plant = JsonText(about, "plant");
  const int link = static_cast<int>(JsonNumber(about, "link", 0));
  if (curve == columns::kPlantCurve) {
    std::string label = "plant P";
    if (link > 0) label += ", link " + std::to_string(link);
    if (!plant.empty()) label += " (" + std::string(plant == "g2" ? "G2" : "G1") + ")";
    return label;
  }
  if (curve == columns::kControllerCurve) {
    if (controller.empty()) return "controller C";
    return "controller C (" + std::string(controller == "pid" ? "PID" : controller) + ")";
  }
  if (curve == columns::kOpenLoopCurve) return "open loop C P";
  if (curve == columns::kReferenceOpenLoopCurve) return "reference open loop (5/s)^1.16";
  return curve;
}

}  // namespace

Figure BodeFigure(const CsvTable& table, const std::string& input, const FigureOptions& options,
                  const FigureScratch& scratch, FigureReport& report) {
  RequireRows(table, 2);
  const nlohmann::json about = SideJson(input, "bode.json");
  const std::vector<double> w = table.Numbers(columns::kFrequency);
  std::vector<std::vector<double>> series = {w};
  double phase_low = 1e300, phase_high = -1e300;
  for (const std::string& curve : options.curves) {
    series.push_back(table.Numbers(columns::MagnitudeDb(curve)));
    series.push_back(table.Numbers(columns::PhaseDeg(curve)));
    for (double p : series.back()) {
      if (std::isfinite(p)) {
        phase_low = std::min(phase_low, p);
        phase_high = std::max(phase_high, p);
      }
    }
  }
  const std::string data = scratch.Data("bode.dat", GnuplotTable(series));

  // Margins of the open loop, if it is drawn, in the bode command's words.
  const bool has_loop = std::find(options.curves.begin(), options.curves.end(),
                                  std::string(columns::kOpenLoopCurve)) != options.curves.end();
  const Margins margins = has_loop ? MarginsOf(about) : Margins{};
  std::string margin_text;
  if (has_loop && !margins.known) {
    report.notes.push_back("no margins marked: bode.json of `bode --out` is not beside the input");
  } else if (has_loop) {
    margin_text = margins.gain_margin_dB
                      ? "Gm = " + Format("%.2f", *margins.gain_margin_dB) + " dB (at " +
                            Format("%.3f", *margins.phase_crossover_rad_s) + " rad/s)"
                      : "Gm = inf (the phase does not reach -180 deg)";
    margin_text += ", ";
    margin_text += margins.phase_margin_deg
                       ? "Pm = " + Format("%.2f", *margins.phase_margin_deg) + " deg (at " +
                             Format("%.3f", *margins.crossover_rad_s) + " rad/s)"
                       : "Pm: no gain crossover";
    report.notes.push_back("margins (bode.json): " + margin_text);
  }

  const std::string controller = JsonText(about, "controller");
  const int link = static_cast<int>(JsonNumber(about, "link", 0));
  std::string what = "Bode diagram";
  if (!controller.empty())
    what += " of the " + std::string(controller == "pid" ? "PID" : controller) + " controller";
  if (link > 0) what += " with link " + std::to_string(link) + "'s plant";
  SetTitle(report, options, what, margin_text);

  auto plot = [&](int offset) {
    std::string line = "plot ";
    for (size_t k = 0; k < options.curves.size(); ++k) {
      const std::string& curve = options.curves[k];
      const bool reference = curve == columns::kReferenceOpenLoopCurve;
      const bool loop = curve == columns::kOpenLoopCurve;
      line += (k ? ", " : "") + data + " using 1:" + std::to_string(2 + 2 * k + offset) +
              " with lines lw " + (loop ? "2.5" : "1.8") + " lc " +
              Rgb(reference ? "#000000" : kSeries[k % kSeriesCount]) + (reference ? " dt 2" : "") +
              " title " + Q(BodeLabel(curve, about));
    }
    return line + "\n";
  };
  // The margins' bars (MATLAB's margin): the gain margin on the magnitude
  // panel, the phase margin on the phase panel, with a dotted line at
  // each crossover through both.
  std::string magnitude_marks, phase_marks;
  if (margins.crossover_rad_s) {
    const std::string wc = N(*margins.crossover_rad_s);
    magnitude_marks +=
        "set arrow from " + wc + ", graph 0 to " + wc + ", graph 1 nohead dt 3 lc rgb 'gray40'\n";
    phase_marks += "set arrow from " + wc + ", graph 0 to " + wc +
                   ", graph 1 nohead dt 3 lc rgb 'gray40'\n"
                   "set arrow from " +
                   wc + ", -180 to " + wc + ", " + N(-180.0 + *margins.phase_margin_deg) +
                   " nohead lw 3 lc " + Rgb(kRed) +
                   " front\n"
                   "set label " +
                   Q("Pm " + Format("%.2f", *margins.phase_margin_deg) + " deg") + " at " + wc +
                   ", " + N(-180.0 + 0.5 * *margins.phase_margin_deg) +
                   " offset 1,0 front boxed tc " + Rgb(kRed) + "\n";
  }
  if (margins.phase_crossover_rad_s) {
    const std::string w180 = N(*margins.phase_crossover_rad_s);
    magnitude_marks += "set arrow from " + w180 + ", graph 0 to " + w180 +
                       ", graph 1 nohead dt 3 lc rgb 'gray40'\n"
                       "set arrow from " +
                       w180 + ", " + N(-*margins.gain_margin_dB) + " to " + w180 +
                       ", 0 nohead lw 3 lc " + Rgb(kRed) +
                       " front\n"
                       "set label " +
                       Q("Gm " + Format("%.2f", *margins.gain_margin_dB) + " dB") + " at " + w180 +
                       ", " + N(-0.5 * *margins.gain_margin_dB) +
                       " offset 1,0 front boxed tc " + Rgb(kRed) + "\n";
    phase_marks += "set arrow from " + w180 + ", graph 0 to " + w180 +
                   ", graph 1 nohead dt 3 lc rgb 'gray40'\n";
  }
  const double span = phase_high - phase_low;
  const double phase_step = span <= 400 ? 45 : 90;
  Figure figure;
  figure.width_in = 7.5;
  figure.height_in = 7.0;
  const double H = figure.height_in;
  figure.commands =
      "set multiplot title " + Heading(report) + "\n" + "set logscale x\nset mxtics 10\n" +
      "set style textbox opaque noborder margins 1, 1\n" + "set key at screen 0.5, screen " +
      N(1.0 - 0.5 / H) + " center top vertical maxrows 2 samplen 3 spacing 1.1\n" +
      PanelBox(0.11, 0.97, 0.53, 1.0 - 1.0 / H) +
      "set ylabel 'magnitude [dB]'\nset format y '%g'\nunset xlabel\nset format x ''\n" +
      "set arrow from graph 0, first 0 to graph 1, first 0 nohead lc rgb 'gray30'\n" +
      magnitude_marks + plot(0) + "unset arrow\nunset label\nunset title\nunset key\n" +
      PanelBox(0.11, 0.97, 0.09, 0.50) + "set format x '%g'\nset xlabel " +
      Q(AxisLabel(columns::kFrequency)) + "\n" + "set ylabel 'phase [deg]'\nset ytics " +
      N(phase_step) + "\n" +
      "set arrow from graph 0, first -180 to graph 1, first -180 nohead lc rgb 'gray30'\n" +
      phase_marks + plot(1) + "unset multiplot\n";
  return figure;
}
// ------------------------------------------------------------------ step ---

Figure StepFigure(const CsvTable& table, const std::string& input, const FigureOptions& options,
                  const FigureScratch& scratch, FigureReport& report) {
  RequireRows(table, 2);
  const nlohmann::json about = SideJson(input, "step.json");
  std::vector<std::vector<double>> series = {table.Numbers(columns::kTime),
                                             table.Numbers(columns::kReferenceModel)};
  std::vector<int> links;
  for (int q = 1; table.Has(columns::StepOutput(q)); ++q) {
    series.push_back(table.Numbers(columns::StepOutput(q)));
    links.push_back(q);
  }
  if (links.empty()) table.Column(columns::StepOutput(1));
  std::vector<int> voltages;
  for (int q : links) {
    if (!table.Has(columns::StepVoltage(q))) continue;
    series.push_back(table.Numbers(columns::StepVoltage(q)));
    voltages.push_back(q);
  }
  const std::string data = scratch.Data("step.dat", GnuplotTable(series));

  std::string context = JsonText(about, "controller");
  if (context == "pid") context = "PID";
  if (about.contains("clamp_enabled") && about["clamp_enabled"].is_boolean()) {
    context += about["clamp_enabled"].get<bool>()
                   ? ", clamp +-" + Format("%g", JsonNumber(about, "v_max_V", 0)) + " V"
                   : ", no clamp";
  }
  SetTitle(report, options, "Closed-loop unit step of each link", context);
  std::string plot = "plot ";
  for (size_t k = 0; k < links.size(); ++k) {
    plot += data + " using 1:" + std::to_string(3 + k) + " with lines lw 2 lc " +
            Rgb(kSeries[k % kSeriesCount]) + " title " + Q("link " + std::to_string(links[k])) +
            ", ";
  }
  plot += data + " using 1:2 with lines lw 2.5 dt 2 lc rgb 'black' title 'reference model'\n";
  Figure figure;
  figure.width_in = 7.0;
  figure.height_in = voltages.empty() ? 4.5 : 6.0;
  const double split = voltages.empty() ? 0.12 : 0.44;
  figure.commands = "set multiplot title " + Heading(report) + "\n" +
                    PanelBox(0.12, 0.97, split + (voltages.empty() ? 0.0 : 0.03), 0.88) +
                    "set ylabel 'tip deflection [mm]'\n"
                    "set key right bottom opaque box\n" +
                    (voltages.empty() ? "set xlabel " + Q(AxisLabel(columns::kTime)) + "\n"
                                      : std::string("set format x ''\n")) +
                    plot;
  if (!voltages.empty()) {
    std::string lower = "plot ";
    // Without a clamp the derivative's kick at t = 0 is orders of
    // magnitude above the rest; the axis spans the voltages after the
    // first kKickFraction of the record, and the kick is named instead.
    constexpr double kKickFraction = 0.02;
    const std::vector<double>& t = series[0];
    double v_peak = 0.0, v_rest = 0.0;
    for (size_t k = 0; k < voltages.size(); ++k) {
      const size_t at = std::find(links.begin(), links.end(), voltages[k]) - links.begin();
      const size_t column = 1 + links.size() + 1 + k;
      lower += (k ? ", " : "") + data + " using 1:" + std::to_string(column + 1) +
               " with lines lw 1.5 lc " + Rgb(kSeries[at % kSeriesCount]) + " notitle";
      for (size_t i = 0; i < t.size(); ++i) {
        const double v = std::abs(series[column][i]);
        if (!std::isfinite(v)) continue;
        v_peak = std::max(v_peak, v);
        if (t[i] >= t.front() + kKickFraction * (t.back() - t.front()))
          v_rest = std::max(v_rest, v);
      }
    }
    const bool clamp = about.contains("clamp_enabled") && about["clamp_enabled"].is_boolean() &&
                       about["clamp_enabled"].get<bool>();
    std::string range;
    if (clamp) {
      const double v_max = JsonNumber(about, "v_max_V", 0);
      lower += ", " + N(v_max) + " with lines dt 2 lc rgb 'gray30' title 'clamp', " + N(-v_max) +
               " with lines dt 2 lc rgb 'gray30' notitle";
    } else if (v_rest > 0.0 && v_peak > 2.0 * v_rest) {
      range = "set yrange [" + N(-1.2 * v_rest) + ":" + N(1.2 * v_rest) +
              "]\n"
              "set label " +
              Q(Format("peak %.3g V at the start, off the scale", v_peak)) +
              " at graph 0.97, graph 0.12 right front\n";
    }
    figure.commands += "set key right top nobox noopaque\n" + PanelBox(0.12, 0.97, 0.11, split) +
                       range + "set format x '%g'\nset xlabel " + Q(AxisLabel(columns::kTime)) +
                       "\n" + "set ylabel 'voltage [V]'\n" + lower + "\n";
  }
  figure.commands += "unset multiplot\n";
  return figure;
}

}  // namespace ipmc::figure_parts
