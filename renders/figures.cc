#include "renders/figures.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "plugin/base/error.h"
#include "plugin/base/numbers.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxInstants = 12;
constexpr int kMinMapRows = 2;
constexpr int kMapColumns = 91;  // x samples along the body in the x-t map

// Colours: measured or realised (blue), reference (black, dashed), voltage
// (red), the clamp's limits (grey), its intervals (pale red), fits.
constexpr char kBlue[] = "#1f5fa8";
constexpr char kRed[] = "#c0392b";
constexpr char kGreen[] = "#2e8b3e";
constexpr char kOrange[] = "#e08a0b";
constexpr char kGrey[] = "#666666";
constexpr char kClampShade[] = "#f6d5d1";
constexpr char kBandShade[] = "#e8eef8";
// Line colours of several instants or groups.
constexpr const char* kSeries[] = {"#1f5fa8", "#c0392b", "#2e8b3e", "#8e44ad",
                                   "#e08a0b", "#17a2b8", "#6d4c41", "#d81b60"};
constexpr int kSeriesCount = sizeof(kSeries) / sizeof(kSeries[0]);

std::string Q(const std::string& text) { return GnuplotQuote(text); }
std::string N(double value) { return GnuplotNumber(value); }
std::string Rgb(const char* colour) { return std::string("rgb '") + colour + "'"; }

std::string Format(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

// "speed [mm/s]" -> "speed": a label as words in a title.
std::string WithoutUnit(const std::string& label) { return label.substr(0, label.find(" [")); }

// A tic step of 1, 2 or 5 x 10^k that cuts `span` into about `count`.
double NiceStep(double span, int count) {
  if (!(span > 0.0)) return 1.0;
  const double raw = span / count;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (double factor : {1.0, 2.0, 5.0}) {
    if (factor * decade >= raw) return factor * decade;
  }
  return 10.0 * decade;
}

// Margins that pin a panel to a box of the canvas (fractions of it).
std::string PanelBox(double left, double right, double bottom, double top) {
  return "set lmargin at screen " + N(left) + "\nset rmargin at screen " + N(right) +
         "\nset bmargin at screen " + N(bottom) + "\nset tmargin at screen " + N(top) + "\n";
}

void RequireRows(const CsvTable& table, size_t rows) {
  if (table.Rows() < rows) {
    throw InputError(InputProblem::kMissing, {table.source()}, "",
                     "needs at least " + std::to_string(rows) + " data rows, has " +
                         std::to_string(table.Rows()));
  }
}

// A JSON file the same command wrote beside `input`; null if there is none
// or it does not parse.
nlohmann::json SideJson(const std::string& input, const std::string& name) {
  std::ifstream in(fs::path(input).parent_path() / name);
  if (!in) return nullptr;
  nlohmann::json json = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  return json.is_object() ? json : nlohmann::json(nullptr);
}

std::string JsonText(const nlohmann::json& json, const char* key) {
  return json.is_object() && json.contains(key) && json[key].is_string()
             ? json[key].get<std::string>()
             : "";
}

double JsonNumber(const nlohmann::json& json, const char* key, double otherwise) {
  return json.is_object() && json.contains(key) && json[key].is_number() ? json[key].get<double>()
                                                                         : otherwise;
}

// What a run's summary.json says it was, for titles: "PID, clamp +-6 V,
// distributed actuation (paper)", or the gait; "" without a summary.
std::string RunDescription(const nlohmann::json& summary) {
  if (summary.is_null()) return "";
  std::string what;
  const std::string controller = JsonText(summary, "controller");
  if (!controller.empty()) {
    what = controller == "pid"          ? "PID"
           : controller == "fractional" ? "fractional integrator"
                                        : controller;
    if (summary.contains("clamp_enabled") && summary["clamp_enabled"].is_boolean()) {
      what += summary["clamp_enabled"].get<bool>()
                  ? ", clamp +-" + Format("%g", JsonNumber(summary, "v_max_V", 0.0)) + " V"
                  : ", no clamp";
    }
    const std::string actuation = JsonText(summary, "actuation");
    if (!actuation.empty()) what += ", " + actuation + " actuation";
  } else {
    what = JsonText(summary, "gait");
  }
  if (summary.contains("inputs") && summary["inputs"].is_object()) {
    const std::string scenario = JsonText(summary["inputs"], "scenario");
    if (!scenario.empty()) what += " (" + fs::path(scenario).stem().string() + ")";
  }
  return what;
}

// The title: the caller's, or what is shown with its context on a second
// line.
void SetTitle(FigureReport& report, const FigureOptions& options, const std::string& what,
              const std::string& context) {
  if (!options.title.empty()) {
    report.title_lines = {options.title};
  } else if (context.empty()) {
    report.title_lines = {what};
  } else {
    report.title_lines = {what, context};
  }
  report.title.clear();
  for (const std::string& line : report.title_lines) {
    report.title += (report.title.empty() ? "" : ": ") + line;
  }
}

std::string Heading(const FigureReport& report) { return GnuplotLines(report.title_lines); }

// ------------------------------------------------------------------ bode ---

struct Margins {
  std::optional<double> crossover_rad_s, phase_margin_deg, phase_at_crossover_deg;
  std::optional<double> phase_crossover_rad_s, gain_margin_db, magnitude_at_phase_crossover_db;
};

// x where the segment (x0, f0)-(x1, f1) crosses f = 0, in log x.
double LogCrossing(double x0, double f0, double x1, double f1) {
  const double t = f0 / (f0 - f1);
  return std::exp(std::log(x0) + t * (std::log(x1) - std::log(x0)));
}

double LogInterpolate(double x0, double y0, double x1, double y1, double x) {
  const double t = (std::log(x) - std::log(x0)) / (std::log(x1) - std::log(x0));
  return y0 + t * (y1 - y0);
}

// The open loop's margins on the CSV's grid: the lowest gain crossover
// (|L| falls through 0 dB) and, of the phase crossovers (phase through
// -180 deg modulo 360), the one whose gain margin is closest to 0 dB.
Margins MarginsOnGrid(const std::vector<double>& w, const std::vector<double>& db,
                      const std::vector<double>& deg) {
  Margins m;
  for (size_t i = 0; i + 1 < w.size(); ++i) {
    if (!m.crossover_rad_s && db[i] >= 0.0 && db[i + 1] < 0.0) {
      const double wc = LogCrossing(w[i], db[i], w[i + 1], db[i + 1]);
      const double phase = LogInterpolate(w[i], deg[i], w[i + 1], deg[i + 1], wc);
      m.crossover_rad_s = wc;
      m.phase_at_crossover_deg = phase;
      m.phase_margin_deg = std::remainder(phase + 180.0, 360.0);
    }
    const double f0 = std::remainder(deg[i] + 180.0, 360.0);
    const double f1 = std::remainder(deg[i + 1] + 180.0, 360.0);
    if ((f0 > 0.0) != (f1 > 0.0) && std::abs(f0 - f1) < 180.0) {
      const double w180 = LogCrossing(w[i], f0, w[i + 1], f1);
      const double magnitude = LogInterpolate(w[i], db[i], w[i + 1], db[i + 1], w180);
      if (!m.gain_margin_db || std::abs(magnitude) < std::abs(*m.magnitude_at_phase_crossover_db)) {
        m.phase_crossover_rad_s = w180;
        m.magnitude_at_phase_crossover_db = magnitude;
        m.gain_margin_db = -magnitude;
      }
    }
  }
  return m;
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

  // Margins of the open loop, if it is drawn.
  Margins margins;
  const auto open_loop =
      std::find(options.curves.begin(), options.curves.end(), std::string(columns::kOpenLoopCurve));
  const bool has_loop = open_loop != options.curves.end();
  std::string margin_text;
  if (has_loop) {
    const size_t k = open_loop - options.curves.begin();
    margins = MarginsOnGrid(w, series[1 + 2 * k], series[2 + 2 * k]);
    margin_text = margins.gain_margin_db
                      ? "Gm = " + Format("%.2f", *margins.gain_margin_db) + " dB (at " +
                            Format("%.4g", *margins.phase_crossover_rad_s) + " rad/s)"
                      : "Gm = inf (the phase does not reach -180 deg)";
    margin_text += ", ";
    margin_text += margins.phase_margin_deg
                       ? "Pm = " + Format("%.1f", *margins.phase_margin_deg) + " deg (at " +
                             Format("%.4g", *margins.crossover_rad_s) + " rad/s)"
                       : "Pm: no gain crossover";
    report.notes.push_back("margins on the grid: " + margin_text);
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
                   wc + ", -180 to " + wc + ", " + N(*margins.phase_at_crossover_deg) +
                   " nohead lw 3 lc " + Rgb(kRed) +
                   " front\n"
                   "set label " +
                   Q("Pm " + Format("%.1f", *margins.phase_margin_deg) + " deg") + " at " + wc +
                   ", " + N(0.5 * (-180.0 + *margins.phase_at_crossover_deg)) +
                   " offset 1,0 front boxed tc " + Rgb(kRed) + "\n";
  }
  if (margins.phase_crossover_rad_s) {
    const std::string w180 = N(*margins.phase_crossover_rad_s);
    magnitude_marks += "set arrow from " + w180 + ", graph 0 to " + w180 +
                       ", graph 1 nohead dt 3 lc rgb 'gray40'\n"
                       "set arrow from " +
                       w180 + ", " + N(*margins.magnitude_at_phase_crossover_db) + " to " + w180 +
                       ", 0 nohead lw 3 lc " + Rgb(kRed) +
                       " front\n"
                       "set label " +
                       Q("Gm " + Format("%.2f", *margins.gain_margin_db) + " dB") + " at " + w180 +
                       ", " + N(0.5 * *margins.magnitude_at_phase_crossover_db) +
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

// -------------------------------------------------------------- tracking ---

std::vector<int> Numbered(const CsvTable& table, std::string (*column)(int)) {
  std::vector<int> found;
  for (int q = 1; table.Has(column(q)); ++q) found.push_back(q);
  return found;
}

// Panels stacked in inches from the top of a canvas `height_in` tall:
// the box of a panel `top_in` below the top, `tall_in` tall.
std::string StackedPanel(double height_in, double top_in, double tall_in, double left = 0.12,
                         double right = 0.97) {
  return PanelBox(left, right, 1.0 - (top_in + tall_in) / height_in, 1.0 - top_in / height_in);
}

// A number of link q's entry in summary.json's "links".
std::optional<double> LinkSummaryNumber(const nlohmann::json& summary, int q, const char* key) {
  if (!summary.is_object() || !summary.contains("links") || !summary["links"].is_array()) {
    return std::nullopt;
  }
  for (const nlohmann::json& link : summary["links"]) {
    if (JsonNumber(link, "link", 0) == q && link.contains(key) && link[key].is_number()) {
      return link[key].get<double>();
    }
  }
  return std::nullopt;
}

// Closed loop: per link, deflection above and voltage below.
Figure LinkTrackingFigure(const CsvTable& table, const std::vector<int>& links,
                          const nlohmann::json& summary, const FigureScratch& scratch,
                          const std::string& heading) {
  const bool clamp = summary.contains("clamp_enabled") && summary["clamp_enabled"].is_boolean() &&
                     summary["clamp_enabled"].get<bool>();
  const double v_max = JsonNumber(summary, "v_max_V", 0.0);
  const std::vector<double> t = table.Numbers(columns::kTime);
  const int n = static_cast<int>(links.size());
  // Inches: title and key, then per link its heading, deflection and
  // voltage panels, then the time axis.
  constexpr double kHead = 1.05, kLinkHeading = 0.3, kDeflection = 1.45, kGap = 0.06,
                   kVoltage = 0.95, kBlock = kLinkHeading + kDeflection + kGap + kVoltage + 0.12,
                   kFoot = 0.5;
  Figure figure;
  figure.width_in = 7.5;
  figure.height_in = kHead + n * kBlock + kFoot;
  const double H = figure.height_in;
  // The deflection panels' key and, below it, the voltage panels', under
  // the title.
  const std::string key_y = N(1.0 - 0.55 / H), voltage_key_y = N(1.0 - 0.75 / H);
  std::string commands = "set multiplot title " + heading + "\n";
  for (int k = 0; k < n; ++k) {
    const int q = links[k];
    const std::vector<double> reference = table.Numbers(columns::Reference(q));
    const std::vector<double> measured = table.Numbers(columns::Measured(q));
    const bool has_voltage = table.Has(columns::Voltage(q));
    const std::vector<double> voltage =
        has_voltage ? table.Numbers(columns::Voltage(q)) : std::vector<double>(t.size(), NAN);
    // The clamp's intervals, as a band from -1.2 to 1.2 V_max where the
    // voltage is at the limit, NaN (a break) elsewhere.
    std::vector<double> shade_low(t.size(), NAN), shade_high(t.size(), NAN);
    size_t at_clamp = 0;
    for (size_t i = 0; clamp && i < t.size(); ++i) {
      if (std::abs(voltage[i]) >= v_max * (1.0 - 1e-9)) {
        shade_low[i] = -1.2 * v_max;
        shade_high[i] = 1.2 * v_max;
        ++at_clamp;
      }
    }
    const std::string data =
        scratch.Data("tracking" + std::to_string(q) + ".dat",
                     GnuplotTable({t, reference, measured, voltage, shade_low, shade_high}));
    const double top = kHead + k * kBlock;
    const bool last = k + 1 == n;
    std::string panel_title = "link " + std::to_string(q);
    if (clamp) {
      // The run's own fraction (every step, summary.json) if it is there,
      // else that of the recorded samples.
      const double fraction =
          LinkSummaryNumber(summary, q, "saturated_fraction")
              .value_or(static_cast<double>(at_clamp) / std::max<size_t>(1, t.size()));
      panel_title += Format(": voltage at the clamp %.1f %% of the time", 100.0 * fraction);
    }
    double deflection_max = 0.0;
    for (size_t i = 0; i < t.size(); ++i) {
      deflection_max = std::max({deflection_max, std::abs(reference[i]), std::abs(measured[i])});
    }
    commands += StackedPanel(H, top + kLinkHeading, kDeflection) + "set title " + Q(panel_title) +
                " offset 0,-0.4\nset format x ''\nunset xlabel\n"
                "set ylabel 'deflection [mm]'\nset ytics " +
                N(NiceStep(2.0 * deflection_max, 4)) + "\nset key at screen 0.545, screen " +
                key_y + " center top horizontal samplen 4\n" + "plot " + data +
                " using 1:2 with lines lw 2 dt 2 lc rgb 'black' " +
                (k == 0 ? "title 'reference'" : "notitle") +
                ", '' using 1:3 with lines lw 1.6 lc " + Rgb(kBlue) + " " +
                (k == 0 ? "title 'measured'" : "notitle") + "\n" + "unset title\n" +
                StackedPanel(H, top + kLinkHeading + kDeflection + kGap, kVoltage) +
                (last ? "set format x '%g'\nset xlabel " + Q(AxisLabel(columns::kTime)) + "\n"
                      : std::string()) +
                "set ylabel 'voltage [V]'\n"
                "set key at screen 0.545, screen " +
                voltage_key_y + " center top horizontal samplen 4\n" +
                (clamp ? "set yrange [" + N(-1.2 * v_max) + ":" + N(1.2 * v_max) + "]\nset ytics " +
                             N(v_max / 2) + "\n"
                       : std::string("set autoscale y\n")) +
                "plot " +
                (clamp ? data + " using 1:5:6 with filledcurves fc " + Rgb(kClampShade) +
                             " fs solid 1.0 notitle, " +
                             (k == 0 ? "keyentry with boxes fs solid 1.0 fc " + Rgb(kClampShade) +
                                           " title 'at the clamp', "
                                     : std::string()) +
                             N(v_max) + " with lines dt 2 lc rgb 'gray30' " +
                             (k == 0 ? "title " + Q("+-" + Format("%g", v_max) + " V clamp")
                                     : std::string("notitle")) +
                             ", " + N(-v_max) + " with lines dt 2 lc rgb 'gray30' notitle, "
                       : std::string()) +
                data + " using 1:4 with lines lw 1.5 lc " + Rgb(kRed) + " " +
                (k == 0 ? "title 'voltage'" : "notitle") +
                "\n"
                "set autoscale y\nset ytics autofreq\n";
  }
  figure.commands = commands + "unset multiplot\n";
  return figure;
}

// Gait: per joint, reference and measured angle.
Figure JointTrackingFigure(const CsvTable& table, const std::vector<int>& joints,
                           const FigureScratch& scratch, const std::string& heading) {
  const std::vector<double> t = table.Numbers(columns::kTime);
  const int n = static_cast<int>(joints.size());
  Figure figure;
  figure.width_in = 7.5;
  figure.height_in = 1.15 + 1.8 * n;
  const double top = 1.0 - 0.95 / figure.height_in, bottom = 0.5 / figure.height_in;
  const double block = (top - bottom) / n;
  std::string commands = "set multiplot title " + heading + "\n";
  for (int k = 0; k < n; ++k) {
    const int j = joints[k];
    const std::string data =
        scratch.Data("joint" + std::to_string(j) + ".dat",
                     GnuplotTable({t, table.Numbers(columns::JointReference(j)),
                                   table.Numbers(columns::JointAngle(j))}));
    const double block_top = top - k * block;
    const bool last = k + 1 == n;
    commands += PanelBox(0.12, 0.97, block_top - block + 0.02, block_top - 0.015) +
                (last ? "set format x '%g'\nset xlabel " + Q(AxisLabel(columns::kTime)) + "\n"
                      : std::string("set format x ''\nunset xlabel\n")) +
                "set ylabel " + Q(AxisLabel(columns::JointAngle(j))) + "\n" +
                (k == 0 ? "set key at screen 0.5, screen " + N(1.0 - 0.6 / figure.height_in) +
                              " center top horizontal samplen 4\n"
                        : std::string("set key off\n")) +
                "plot " + data +
                " using 1:2 with lines lw 2 dt 2 lc rgb 'black' title "
                "'reference', '' using 1:3 with lines lw 1.8 lc " +
                Rgb(kBlue) + " title 'measured'\n";
  }
  figure.commands = commands + "unset multiplot\n";
  return figure;
}

Figure TrackingFigure(const CsvTable& table, const std::string& input, const FigureOptions& options,
                      const FigureScratch& scratch, FigureReport& report) {
  RequireRows(table, 2);
  const nlohmann::json summary = SideJson(input, "summary.json");
  const std::vector<int> links = Numbered(table, &columns::Reference);
  if (!links.empty()) {
    SetTitle(report, options, "Tracking of each link's relative tip deflection",
             RunDescription(summary));
    return LinkTrackingFigure(table, links, summary, scratch, Heading(report));
  }
  const std::vector<int> joints = Numbered(table, &columns::JointReference);
  if (!joints.empty()) {
    SetTitle(report, options, "Joint angles, reference and measured", RunDescription(summary));
    return JointTrackingFigure(table, joints, scratch, Heading(report));
  }
  throw InputError(InputProblem::kMissing, {table.source()}, columns::Reference(1),
                   "no column '" + columns::Reference(1) +
                       "' (plot tracking needs reference<q>_mm and measured<q>_mm of a "
                       "closed-loop run, or q_ref<j>_rad and q<j>_rad of a gait)");
}

// ------------------------------------------------------ body in the head ---

struct Point2 {
  double x = 0.0, y = 0.0;
};

// The body per sample as points (head, tip 1, ..., tip n) in the head's
// frame [mm]: realised from the tips, ideal from the references (see the
// header).
struct BodyRecord {
  std::vector<double> t_s;
  std::vector<std::vector<Point2>> realised;
  std::vector<std::vector<Point2>> ideal;  // empty without reference columns
};

// A gait's ideal body: segment k keeps the realised body's mean length
// from point k-1 to tip k and turns from segment k-1 (the head's axis for
// k = 1) by the reference angle of joint k, the hinge at its root; joints
// without a reference column stay straight.
std::vector<std::vector<Point2>> GaitIdeal(const CsvTable& table,
                                           const std::vector<std::vector<Point2>>& realised) {
  const size_t samples = realised.size();
  const size_t tips = realised.front().size() - 1;
  std::vector<double> segment_mm(tips, 0.0);
  std::vector<std::vector<double>> reference(tips);
  for (size_t k = 0; k < tips; ++k) {
    const int joint = static_cast<int>(k) + 1;
    if (table.Has(columns::JointReference(joint))) {
      reference[k] = table.Numbers(columns::JointReference(joint));
    }
    for (size_t i = 0; i < samples; ++i) {
      const std::vector<Point2>& p = realised[i];
      segment_mm[k] += std::hypot(p[k + 1].x - p[k].x, p[k + 1].y - p[k].y) / samples;
    }
  }
  std::vector<std::vector<Point2>> ideal(samples);
  for (size_t i = 0; i < samples; ++i) {
    Point2 point;
    double direction = 0.0;
    ideal[i].push_back(point);
    for (size_t k = 0; k < tips; ++k) {
      if (!reference[k].empty()) direction += reference[k][i];
      point.x += segment_mm[k] * std::cos(direction);
      point.y += segment_mm[k] * std::sin(direction);
      ideal[i].push_back(point);
    }
  }
  return ideal;
}

BodyRecord ReadBodyRecord(const CsvTable& table) {
  RequireRows(table, 1);
  BodyRecord body;
  body.t_s = table.Numbers(columns::kTime);
  const std::vector<double> head_x = table.Numbers(columns::kHeadX);
  const std::vector<double> head_y = table.Numbers(columns::kHeadY);
  const std::vector<double> yaw = table.Numbers(columns::kYaw);
  std::vector<std::vector<double>> tip_x, tip_y;
  for (int k = 1; k == 1 || table.Has(columns::TipX(k)); ++k) {
    tip_x.push_back(table.Numbers(columns::TipX(k)));
    tip_y.push_back(table.Numbers(columns::TipY(k)));
  }
  const size_t samples = body.t_s.size();
  const size_t tips = tip_x.size();
  body.realised.resize(samples);
  for (size_t i = 0; i < samples; ++i) {
    const double c = std::cos(yaw[i]), s = std::sin(yaw[i]);
    body.realised[i].push_back({0.0, 0.0});
    for (size_t k = 0; k < tips; ++k) {
      const double dx = tip_x[k][i] - head_x[i], dy = tip_y[k][i] - head_y[i];
      body.realised[i].push_back({c * dx + s * dy, -s * dx + c * dy});
    }
  }
  if (!table.Has(columns::Reference(1))) {
    if (table.Has(columns::JointReference(1))) body.ideal = GaitIdeal(table, body.realised);
    return body;
  }

  // Per segment k (point k-1 to tip k): mean length, and the length L_k
  // that maps the measured deflection onto the realised turn angle.
  std::vector<double> segment_mm(tips, 0.0), link_mm(tips, 0.0);
  std::vector<std::vector<double>> reference(tips);
  for (size_t k = 0; k < tips; ++k) {
    const int link = static_cast<int>(k) + 1;
    double numerator = 0.0, denominator = 0.0;
    const bool referenced = table.Has(columns::Reference(link));
    std::vector<double> measured;
    if (referenced) {
      reference[k] = table.Numbers(columns::Reference(link));
      measured = table.Numbers(columns::Measured(link));
    }
    for (size_t i = 0; i < samples; ++i) {
      const std::vector<Point2>& p = body.realised[i];
      segment_mm[k] += std::hypot(p[k + 1].x - p[k].x, p[k + 1].y - p[k].y) / samples;
      if (!referenced) continue;
      const double direction = std::atan2(p[k + 1].y - p[k].y, p[k + 1].x - p[k].x);
      const double previous = k == 0 ? 0.0 : std::atan2(p[k].y - p[k - 1].y, p[k].x - p[k - 1].x);
      const double sine = std::sin(std::remainder(direction - previous, kTwoPi));
      numerator += measured[i] * sine;
      denominator += sine * sine;
    }
    const double fitted = denominator > 0.0 ? numerator / denominator : 0.0;
    link_mm[k] = std::isfinite(fitted) && fitted > 0.0 ? fitted : segment_mm[k];
  }
  body.ideal.resize(samples);
  for (size_t i = 0; i < samples; ++i) {
    Point2 point;
    double direction = 0.0;
    body.ideal[i].push_back(point);
    for (size_t k = 0; k < tips; ++k) {
      if (!reference[k].empty()) {
        direction += std::asin(std::clamp(reference[k][i] / link_mm[k], -1.0, 1.0));
      }
      point.x += segment_mm[k] * std::cos(direction);
      point.y += segment_mm[k] * std::sin(direction);
      body.ideal[i].push_back(point);
    }
  }
  return body;
}

size_t NearestSample(const std::vector<double>& t_s, double t) {
  size_t best = 0;
  for (size_t i = 1; i < t_s.size(); ++i) {
    if (std::abs(t_s[i] - t) < std::abs(t_s[best] - t)) best = i;
  }
  return best;
}

// The wave period: the option, else summary.json's period_s, else 0.
double Period(const FigureOptions& options, const nlohmann::json& summary) {
  if (options.period_s > 0.0) return options.period_s;
  const double period = JsonNumber(summary, "period_s", 0.0);
  return std::isfinite(period) && period > 0.0 ? period : 0.0;
}

std::string PointsBlock(const std::vector<Point2>& points) {
  std::string text;
  for (const Point2& p : points) text += GnuplotValue(p.x) + " " + GnuplotValue(p.y) + "\n";
  return text;
}

Figure WaveformFigure(const CsvTable& table, const std::string& input, const FigureOptions& options,
                      const FigureScratch& scratch, FigureReport& report) {
  const nlohmann::json summary = SideJson(input, "summary.json");
  const BodyRecord body = ReadBodyRecord(table);
  const bool with_ideal = !body.ideal.empty();
  std::vector<size_t> instants;
  if (!options.times_s.empty()) {
    for (double t : options.times_s) instants.push_back(NearestSample(body.t_s, t));
  } else {
    const double t_first = body.t_s.front(), t_last = body.t_s.back();
    double period = Period(options, summary);
    if (period <= 0.0 || period > t_last - t_first) period = t_last - t_first;
    for (int k = 1; k <= options.instants; ++k) {
      instants.push_back(NearestSample(body.t_s, t_last - period + period * k / options.instants));
    }
  }
  std::string text;
  double x_low = 0.0, x_high = 0.0, y_max = 0.0;
  for (size_t sample : instants) {
    text += PointsBlock(body.realised[sample]) + "\n\n" +
            (with_ideal ? PointsBlock(body.ideal[sample]) : std::string("NaN NaN\n")) + "\n\n";
    for (const auto* shapes : {&body.realised, &body.ideal}) {
      if (shapes->empty()) continue;
      for (const Point2& p : (*shapes)[sample]) {
        x_low = std::min(x_low, p.x);
        x_high = std::max(x_high, p.x);
        y_max = std::max(y_max, std::abs(p.y));
      }
    }
  }
  const std::string data = scratch.Data("waveform.dat", text);
  SetTitle(report, options,
           with_ideal ? "Body shape in the head's frame, ideal and realised"
                      : "Body shape in the head's frame",
           RunDescription(summary));
  std::string plot = "plot ";
  for (size_t k = 0; k < instants.size(); ++k) {
    const std::string colour = Rgb(kSeries[k % kSeriesCount]);
    plot += (k ? ", " : "") + data + " index " + std::to_string(2 * k) +
            " using 1:2 with linespoints lw 2 pt 7 ps 0.9 lc " + colour + " title " +
            Q(Format("t = %.4g s", body.t_s[instants[k]]));
    if (with_ideal) {
      plot += ", '' index " + std::to_string(2 * k + 1) +
              " using 1:2 with linespoints lw 1.5 dt 2 pt 6 ps 0.9 lc " + colour + " notitle";
    }
  }
  if (with_ideal) {
    plot +=
        ", NaN with lines lw 2 lc rgb 'black' title 'realised (solid)', NaN with lines lw 1.5 "
        "dt 2 lc rgb 'black' title 'ideal (dashed)'";
  }
  const double margin = 0.03 * (x_high - x_low);
  Figure figure;
  figure.width_in = 7.5;
  figure.height_in = 4.4;
  figure.commands = "set title " + Heading(report) + "\n" +
                    "set xlabel 'x along the body from the head [mm]' offset 0,0.4\n"
                    "set ylabel 'y lateral [mm]'\n"
                    "set xrange [" +
                    N(x_low - margin) + ":" + N(x_high + margin) + "]\n" + "set yrange [" +
                    N(-1.15 * std::max(y_max, 1e-3)) + ":" + N(1.15 * std::max(y_max, 1e-3)) +
                    "]\n" +
                    "set key outside bottom center horizontal maxrows 2 samplen 4 spacing 1.1\n"
                    "set xzeroaxis lt 1 lc rgb 'gray40'\n" +
                    plot + "\n";
  return figure;
}

// ------------------------------------------------------------ x-t map ---

// Evenly spread sample indices, at most `count`.
std::vector<size_t> Thinned(size_t samples, int count) {
  std::vector<size_t> chosen;
  if (samples <= static_cast<size_t>(count)) {
    for (size_t i = 0; i < samples; ++i) chosen.push_back(i);
    return chosen;
  }
  for (int k = 0; k < count; ++k) {
    chosen.push_back(static_cast<size_t>(
        std::lround(static_cast<double>(k) * static_cast<double>(samples - 1) / (count - 1))));
  }
  return chosen;
}

// y at x along the polyline (linear between its points, which run along
// +x); NaN beyond its ends.
double LateralAt(const std::vector<Point2>& shape, double x) {
  for (size_t k = 0; k + 1 < shape.size(); ++k) {
    const double x0 = shape[k].x, x1 = shape[k + 1].x;
    if ((x >= x0 && x <= x1) || (x >= x1 && x <= x0)) {
      if (x1 == x0) return shape[k].y;
      return shape[k].y + (x - x0) / (x1 - x0) * (shape[k + 1].y - shape[k].y);
    }
  }
  return NAN;
}

// Rows "x t y", one block per sample, for a map drawn `with image`.
std::string MapData(const std::vector<std::vector<Point2>>& shapes, const std::vector<double>& t_s,
                    const std::vector<size_t>& samples, double length_mm, double* y_max) {
  std::string text;
  for (size_t i : samples) {
    for (int c = 0; c < kMapColumns; ++c) {
      const double x = length_mm * c / (kMapColumns - 1);
      const double y = LateralAt(shapes[i], x);
      if (std::isfinite(y)) *y_max = std::max(*y_max, std::abs(y));
      text += GnuplotValue(x) + " " + GnuplotValue(t_s[i]) + " " + GnuplotValue(y) + "\n";
    }
    text += "\n";
  }
  return text;
}

Figure SurfaceFigure(const CsvTable& table, const std::string& input, const FigureOptions& options,
                     const FigureScratch& scratch, FigureReport& report) {
  const nlohmann::json summary = SideJson(input, "summary.json");
  const BodyRecord body = ReadBodyRecord(table);
  RequireRows(table, 2);
  const std::vector<size_t> samples = Thinned(body.t_s.size(), options.max_lines);
  const bool with_ideal = !body.ideal.empty();
  double length_mm = 0.0;
  for (size_t i : samples) length_mm = std::max(length_mm, body.realised[i].back().x);
  if (with_ideal) {
    for (size_t i : samples) length_mm = std::max(length_mm, body.ideal[i].back().x);
  }
  if (!(length_mm > 0.0)) length_mm = 1.0;
  double y_max = 0.0;
  const std::string realised = scratch.Data(
      "map_realised.dat", MapData(body.realised, body.t_s, samples, length_mm, &y_max));
  const std::string ideal =
      with_ideal
          ? scratch.Data("map_ideal.dat", MapData(body.ideal, body.t_s, samples, length_mm, &y_max))
          : "";
  if (!(y_max > 0.0)) y_max = 1.0;
  SetTitle(report, options, "Lateral deflection along the body over time", RunDescription(summary));
  // Each sample of the map is a pixel of `with image` centred on its
  // (x, t); the axes end at the body's ends and the record's. NaN (beyond
  // the bent body's end) must stay a blank pixel, not a missing one, or
  // the rest of its row would shift.
  const std::string common =
      "unset datafile missing\nunset grid\nunset key\nset tics out front\n"
      "set palette defined (-1 '#2166ac', -0.5 '#92c5de', 0 '#f7f7f7', 0.5 '#f4a582', 1 "
      "'#b2182b')\n"
      "set cbrange [" +
      N(-y_max) + ":" + N(y_max) +
      "]\n"
      "set xrange [0:" +
      N(length_mm) +
      "]\n"
      "set yrange [" +
      N(body.t_s[samples.front()]) + ":" + N(body.t_s[samples.back()]) +
      "]\n"
      "set xlabel 'x along the body from the head [mm]'\n"
      "set ylabel " +
      Q(AxisLabel(columns::kTime)) + "\n";
  Figure figure;
  figure.height_in = 4.6;
  const double H = figure.height_in;
  const double top = 1.0 - 1.0 / H, bottom = 0.8 / H;
  std::string commands = "set multiplot title " + Heading(report) + "\n" + common;
  const std::string colour_bar = "set cblabel 'lateral deflection y [mm]'\nset cbtics out\n";
  if (with_ideal) {
    figure.width_in = 9.0;
    commands += PanelBox(0.08, 0.45, bottom, top) +
                "unset colorbox\nset title 'ideal (references)'\n"
                "plot " +
                ideal + " using 1:2:3 with image\n" + PanelBox(0.50, 0.87, bottom, top) +
                "set colorbox user origin screen 0.895, screen " + N(bottom) +
                " size screen 0.02, screen " + N(top - bottom) + "\n" + colour_bar +
                "set title 'realised (tips)'\nset ylabel ''\nset format y ''\n"
                "plot " +
                realised + " using 1:2:3 with image\n";
  } else {
    figure.width_in = 6.5;
    commands += PanelBox(0.12, 0.80, bottom, top) +
                "set colorbox user origin screen 0.84, screen " + N(bottom) +
                " size screen 0.03, screen " + N(top - bottom) + "\n" + colour_bar +
                "set title 'realised (tips)'\nplot " + realised + " using 1:2:3 with image\n";
  }
  figure.commands = commands + "unset multiplot\n";
  return figure;
}

// ------------------------------------------------------------ trajectory ---

Figure TrajectoryFigure(const CsvTable& table, const std::string& input,
                        const FigureOptions& options, const FigureScratch& scratch,
                        FigureReport& report) {
  RequireRows(table, 2);
  const nlohmann::json summary = SideJson(input, "summary.json");
  const std::vector<double> t = table.Numbers(columns::kTime);
  const std::vector<double> com_x = table.Numbers(columns::kComX);
  const std::vector<double> com_y = table.Numbers(columns::kComY);
  const std::vector<double> head_x = table.Numbers(columns::kHeadX);
  const std::vector<double> head_y = table.Numbers(columns::kHeadY);
  const size_t n = t.size();
  // Each point relative to its own start, in the swimming frame of
  // sim/core/swim_meter.h: "along" is -x (head first), "across" +y. The
  // head and the centre of mass are half a body apart, many times their
  // displacement, so each path starts at the origin.
  std::vector<double> com_along(n), com_across(n), head_along(n), head_across(n);
  for (size_t i = 0; i < n; ++i) {
    com_along[i] = -(com_x[i] - com_x[0]);
    com_across[i] = com_y[i] - com_y[0];
    head_along[i] = -(head_x[i] - head_x[0]);
    head_across[i] = head_y[i] - head_y[0];
  }
  const std::string data = scratch.Data(
      "trajectory.dat", GnuplotTable({t, com_along, com_across, head_along, head_across}));
  // The start of every cycle, on both paths.
  const double period = Period(options, summary);
  std::string markers;
  std::string cycle_lines;
  if (period > 0.0) {
    for (int k = 0; k * period <= t.back() + 1e-9 * period; ++k) {
      const size_t i = NearestSample(t, k * period);
      markers += GnuplotValue(com_along[i]) + " " + GnuplotValue(com_across[i]) + " " +
                 GnuplotValue(head_along[i]) + " " + GnuplotValue(head_across[i]) + "\n";
      cycle_lines += "set arrow from " + N(k * period) + ", graph 0 to " + N(k * period) +
                     ", graph 1 nohead dt 3 lc rgb 'gray60'\n";
    }
  }
  const std::string marker_data =
      scratch.Data("cycles.dat", markers.empty() ? "NaN NaN NaN NaN\n" : markers);
  if (summary.is_object() && summary.contains("per_cycle") && summary["per_cycle"].is_array() &&
      !summary["per_cycle"].empty()) {
    report.notes.push_back(
        "last cycle: " +
        Format("%.4g", JsonNumber(summary["per_cycle"].back(), "com_along_mm", NAN)) +
        " mm along the axis");
  }
  SetTitle(report, options, "Swimming: net displacement and path in the plane",
           RunDescription(summary));
  Figure figure;
  figure.width_in = 7.5;
  figure.height_in = 7.0;
  const double H = figure.height_in;
  const std::string cycle_key = markers.empty() ? "notitle" : "title 'start of a cycle'";
  figure.commands =
      "set multiplot title " + Heading(report) + "\n" + StackedPanel(H, 0.95, 2.45) + cycle_lines +
      "set title 'displacement against time' offset 0,-0.4\n"
      "set xlabel " +
      Q(AxisLabel(columns::kTime)) +
      " offset 0,0.3\n"
      "set ylabel 'displacement [mm]'\n"
      "set key left top samplen 3 box opaque\n"
      "plot " +
      data + " using 1:2 with lines lw 2.5 lc " + Rgb(kBlue) +
      " title 'centre of mass, along', '' using 1:3 with lines lw 1.5 dt (6,4) lc " + Rgb(kBlue) +
      " title 'centre of mass, across', '' using 1:4 with lines lw 1.2 lc " + Rgb(kOrange) +
      " title 'head, along'\n"
      "unset arrow\n"
      "set title 'path in the plane (each from its start)' offset 0,-0.4\n"

      "set xlabel 'along the swimming axis [mm] (head first)' offset 0,0.3\n"
      "set ylabel 'across [mm]'\n"
      "set key noopaque nobox at screen 0.98, screen " +
      N(1.0 - 4.35 / H) + " right top vertical samplen 2\n" +
      StackedPanel(H, 4.35, 2.05, 0.12, 0.72) + "plot " + data + " using 4:5 with lines lw 1 lc " +
      Rgb(kOrange) + " title 'head', " + data + " using 2:3 with lines lw 2.5 lc " + Rgb(kBlue) +
      " title 'centre of mass', " + marker_data +
      " using 1:2 with points pt 7 ps 0.9 lc rgb 'black' " + cycle_key + ", " + marker_data +
      " using 3:4 with points pt 7 ps 0.9 lc rgb 'black' notitle\n"
      "unset multiplot\n";
  return figure;
}

// -------------------------------------------------------- identification ---

Figure IdentificationFigure(const CsvTable& table, const std::string& input,
                            const FigureOptions& options, const FigureScratch& scratch,
                            FigureReport& report) {
  RequireRows(table, 2);
  const nlohmann::json about = SideJson(input, "identification.json");
  const std::vector<double> w = table.Numbers(columns::kFrequency);
  const std::vector<double> coherence = table.Numbers(columns::kCoherence);
  const std::vector<double> in_band = table.Numbers(columns::kInBand);
  std::vector<std::vector<double>> series = {w, coherence};
  for (const char* curve : {columns::kMeasuredCurve, columns::kP1Curve, columns::kP2Curve}) {
    series.push_back(table.Numbers(columns::MagnitudeDb(curve)));
    series.push_back(table.Numbers(columns::PhaseDeg(curve)));
  }
  // The measured phase unwrapped onto G1's (within +-180 deg of it): Welch
  // gives it modulo 360 deg, and past the band, where the coherence falls,
  // its jumps would set the scale.
  for (size_t i = 0; i < w.size(); ++i) {
    series[3][i] = series[4][i] + std::remainder(series[3][i] - series[4][i], 360.0);
  }
  // Measured points inside and outside the band, apart.
  std::vector<double> db_in(w.size(), NAN), deg_in(w.size(), NAN);
  double band_low = 0.0, band_high = 0.0;
  double phase_low = 1e300, phase_high = -1e300;
  for (size_t i = 0; i < w.size(); ++i) {
    if (in_band[i] == 0.0) continue;
    db_in[i] = series[2][i];
    deg_in[i] = series[3][i];
    band_low = band_low == 0.0 ? w[i] : std::min(band_low, w[i]);
    band_high = std::max(band_high, w[i]);
    for (int c : {3, 5, 7}) {
      phase_low = std::min(phase_low, series[c][i]);
      phase_high = std::max(phase_high, series[c][i]);
    }
  }
  series.push_back(db_in);
  series.push_back(deg_in);
  const std::string data = scratch.Data("identification.dat", GnuplotTable(series));
  const std::string output = JsonText(about, "output"), in = JsonText(about, "input");
  SetTitle(report, options, "Identified frequency response: Welch H1 and the Levy fits G1, G2",
           !output.empty() && !in.empty()
               ? WithoutUnit(AxisLabel(output)) + " per " + WithoutUnit(AxisLabel(in))
               : "");
  const bool has_band = band_high > band_low;
  // The band, and a factor kBandMargin beyond it on either side: the
  // figure is about the fit (as Fig. 7), not the response far outside.
  constexpr double kBandMargin = 3.0;
  const std::string band = has_band ? "set object 1 rect from " + N(band_low) + ", graph 0 to " +
                                          N(band_high) + ", graph 1 back fc " + Rgb(kBandShade) +
                                          " fs solid 1.0 noborder\n" + "set xrange [" +
                                          N(band_low / kBandMargin) + ":" +
                                          N(band_high * kBandMargin) + "]\n"
                                    : "";
  const double phase_step = has_band && phase_high - phase_low > 200.0 ? 90.0 : 45.0;
  // The phase axis spans the band's phases in whole steps.
  const std::string phase_range =
      has_band ? "set yrange [" + N(phase_step * (std::floor(phase_low / phase_step) - 0.5)) + ":" +
                     N(phase_step * (std::ceil(phase_high / phase_step) + 0.5)) + "]\n"
               : "";
  auto panel = [&](int measured, int in_band_column, int g1, int g2) {
    return "plot " + data + " using 1:" + std::to_string(measured) +
           " with points pt 7 ps 0.35 lc rgb 'gray60' title 'measured', '' using 1:" +
           std::to_string(in_band_column) + " with points pt 7 ps 0.45 lc " + Rgb(kBlue) +
           " title 'measured, in the fits'' band', '' using 1:" + std::to_string(g1) +
           " with lines lw 2 lc " + Rgb(kRed) +
           " title 'G1 (eq. 5)', '' using 1:" + std::to_string(g2) +
           " with lines lw 2 dt (6,4) lc " + Rgb(kGreen) + " title 'G2 (eq. 6)'\n";
  };
  Figure figure;
  figure.width_in = 7.0;
  figure.height_in = 7.0;
  const double H = figure.height_in;
  figure.commands = "set multiplot title " + Heading(report) + "\n" +
                    "set logscale x\nset mxtics 10\n" + band + StackedPanel(H, 0.85, 2.4) +
                    "set format x ''\nset ylabel 'magnitude [dB]'\n"
                    "set key left bottom opaque box samplen 2 spacing 1.1\n" +
                    panel(3, 9, 5, 7) + "set key off\n" + StackedPanel(H, 3.45, 1.7) + phase_range +
                    "set ylabel 'phase [deg]'\nset ytics " + N(phase_step) + "\n" +
                    panel(4, 10, 6, 8) + StackedPanel(H, 5.35, 1.0) +
                    "set format x '%g'\nset xlabel " + Q(AxisLabel(columns::kFrequency)) + "\n" +
                    "set ylabel 'coherence'\nset yrange [0:1.05]\nset ytics 0.5\n"
                    "plot " +
                    data + " using 1:2 with lines lw 1.5 lc " + Rgb(kGrey) +
                    " notitle\n"
                    "unset multiplot\n";
  return figure;
}

// ----------------------------------------------------------------- sweep ---

// A sweep column, or one element of an array column: "link_lengths_mm[0]".
class SweepAxis {
 public:
  SweepAxis(const CsvTable& table, const std::string& spec) : name_(spec) {
    std::string column = spec;
    const size_t open = spec.find('[');
    if (open != std::string::npos && spec.back() == ']') {
      column = spec.substr(0, open);
      const std::string index = spec.substr(open + 1, spec.size() - open - 2);
      const std::optional<long> value = ParseInteger(index);
      if (!value || *value < 0) {
        throw FieldError(
            table.source() + ": column " + spec + ": the element index must be a whole number >= 0",
            "--x", "a whole number >= 0 in NAME[i]");
      }
      element_ = *value;
    }
    column_ = table.Column(column);
  }

  // The field (or its array element) of `row` as text.
  std::string Text(const CsvTable& table, size_t row) const {
    const std::string& text = table.Text(row, column_);
    if (element_ < 0) return text;
    const nlohmann::json array = nlohmann::json::parse(text, nullptr, false);
    if (!array.is_array() || element_ >= static_cast<long>(array.size())) {
      throw InputError(
          InputProblem::kBadValue, {table.source(), static_cast<std::uint32_t>(table.Line(row))},
          name_, "column " + name_ + ": '" + text + "' has no element " + std::to_string(element_));
    }
    const nlohmann::json& value = array[element_];
    return value.is_string() ? value.get<std::string>() : value.dump();
  }

 private:
  std::string name_;
  size_t column_ = 0;
  long element_ = -1;
};

Figure SweepFigure(const CsvTable& table, const std::string&, const FigureOptions& options,
                   const FigureScratch& scratch, FigureReport& report) {
  const SweepAxis x_axis(table, options.x_column);
  const size_t y_column = table.Column(options.y_column);
  const bool grouped = !options.group_column.empty();
  const std::optional<SweepAxis> group_axis =
      grouped ? std::optional<SweepAxis>(SweepAxis(table, options.group_column)) : std::nullopt;
  const bool has_status = table.Has(columns::kStatus);
  const size_t status_column = has_status ? table.Column(columns::kStatus) : 0;

  std::vector<size_t> rows;
  for (size_t r = 0; r < table.Rows(); ++r) {
    if (!has_status || table.Text(r, status_column) == columns::kStatusOk) rows.push_back(r);
  }
  if (rows.empty()) {
    throw InputError(InputProblem::kBadValue, {table.source()}, columns::kStatus,
                     std::string("no row with status ") + columns::kStatusOk + " to plot");
  }
  bool numeric_x = true;
  for (size_t r : rows) numeric_x = numeric_x && ParseDouble(x_axis.Text(table, r)).has_value();
  std::vector<std::string> categories;  // distinct x values, non-numeric x
  std::vector<std::string> groups;      // distinct group values, in order
  std::map<std::string, std::vector<std::pair<double, double>>> points;
  for (size_t r : rows) {
    const std::string group = grouped ? group_axis->Text(table, r) : "";
    if (std::find(groups.begin(), groups.end(), group) == groups.end()) groups.push_back(group);
    double x = 0.0;
    const std::string value = x_axis.Text(table, r);
    if (numeric_x) {
      x = *ParseDouble(value);
    } else {
      auto at = std::find(categories.begin(), categories.end(), value);
      if (at == categories.end()) at = categories.insert(categories.end(), value);
      x = static_cast<double>(at - categories.begin());
    }
    points[group].push_back({x, table.Number(r, y_column)});
  }
  std::string text;
  for (const std::string& group : groups) {
    std::vector<std::pair<double, double>>& curve = points[group];
    std::stable_sort(curve.begin(), curve.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [x, y] : curve) text += GnuplotValue(x) + " " + GnuplotValue(y) + "\n";
    text += "\n\n";
  }
  const std::string data = scratch.Data("sweep.dat", text);

  std::string what = WithoutUnit(AxisLabel(options.y_column)) + " against " +
                     WithoutUnit(AxisLabel(options.x_column));
  what[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(what[0])));
  SetTitle(report, options, what,
           grouped ? "one curve per " + WithoutUnit(AxisLabel(options.group_column)) : "");
  // The key below the axes, so that it covers no point.
  std::string commands = "set title " + Heading(report) + "\n" + "set xlabel " +
                         Q(AxisLabel(options.x_column)) + "\nset ylabel " +
                         Q(AxisLabel(options.y_column)) + "\n" +
                         "set key below horizontal reverse Left samplen 3 spacing 1.1\n";
  if (options.log_x) commands += "set logscale x\n";
  if (options.log_y) commands += "set logscale y\n";
  if (!numeric_x) {
    commands += "set xrange [-0.5:" + N(categories.size() - 0.5) + "]\nset xtics (";
    for (size_t k = 0; k < categories.size(); ++k) {
      commands += (k ? ", " : "") + Q(categories[k]) + " " + std::to_string(k);
    }
    commands += ")\n";
  } else {
    commands += "set offsets graph 0.03, graph 0.03, graph 0.05, graph 0.05\n";
  }
  // Numeric group values carry the group column's unit in the key.
  std::string group_unit;
  if (grouped) {
    const std::string group_label = AxisLabel(options.group_column);
    const size_t open = group_label.find(" [");
    if (open != std::string::npos && group_label.back() == ']') {
      group_unit = " " + group_label.substr(open + 2, group_label.size() - open - 3);
    }
  }
  std::string plot = "plot ";
  for (size_t k = 0; k < groups.size(); ++k) {
    const std::string label = grouped ? groups[k] + (ParseDouble(groups[k]) ? group_unit : "")
                                      : AxisLabel(options.y_column);
    plot += (k ? ", " : "") + data + " index " + std::to_string(k) + " using 1:2 with " +
            (numeric_x ? "linespoints lw 2" : "points") + " pt 7 ps 1.1 lc " +
            Rgb(kSeries[k % kSeriesCount]) + " title " + Q(label);
  }
  Figure figure;
  figure.width_in = 7.0;
  figure.height_in = 5.0;
  figure.commands = commands + plot + "\n";
  return figure;
}

// ---------------------------------------------------------------- labels ---

struct LabelEntry {
  const char* column;
  const char* label;
};

// Every column the program's CSV files and sweep tables carry that a
// figure puts on an axis, with its label and unit.
constexpr LabelEntry kLabels[] = {
    {"time_s", "time t [s]"},
    {"w_rad_s", "angular frequency w [rad/s]"},
    {"frequency_Hz", "frequency f [Hz]"},
    {"com_x_mm", "centre of mass x [mm]"},
    {"com_y_mm", "centre of mass y [mm]"},
    {"head_x_mm", "head x [mm]"},
    {"head_y_mm", "head y [mm]"},
    {"yaw_rad", "head yaw [rad]"},
    {"coherence", "coherence"},
    {"mean_speed_along_mm_s", "mean speed along the swimming axis [mm/s]"},
    {"last_cycle_com_along_mm", "centre of mass swim in the last cycle [mm]"},
    {"reynolds_tip", "Reynolds number, tip"},
    {"reynolds_swim", "Reynolds number, swimming"},
    {"actuation", "actuation"},
    {"plants", "link plants"},
    {"cycles", "cycles"},
    {"segments_per_link", "rigid segments per link"},
    {"timestep_s", "time step [s]"},
    {"waveform.frequency_Hz", "wave frequency f [Hz]"},
    {"waveform.wavelength_mm", "wavelength [mm]"},
    {"waveform.c0_um", "wave amplitude c0 [um]"},
    {"waveform.c1_um_per_mm", "wave amplitude slope c1 [um/mm]"},
    {"waveform.c2_um_per_mm2", "wave amplitude curvature c2 [um/mm^2]"},
    {"waveform.c_um", "wave amplitude c [um/mm^alpha]"},
    {"waveform.alpha", "wave growth exponent alpha"},
    {"fluid.viscosity_Pa_s", "viscosity mu [Pa s]"},
    {"controller.kind", "controller"},
    {"controller.kp", "proportional gain Kp [V/mm]"},
    {"controller.ki", "integral gain Ki [V/(mm s)]"},
    {"controller.kd", "derivative gain Kd [V s/mm]"},
    {"controller.v_max_V", "voltage limit [V]"},
    {"controller.sample_rate_Hz", "controller sample rate [Hz]"},
    {"link_lengths_mm", "link lengths [mm]"},
};

// Per-link sweep results "link<q>_<result>".
constexpr LabelEntry kLinkResultLabels[] = {
    {"iae_mm_s", "IAE [mm s]"},
    {"itae_mm_s2", "ITAE [mm s^2]"},
    {"rms_voltage_V", "RMS voltage [V]"},
    {"clamped_fraction", "fraction of samples at the clamp"},
};

// Numbered columns PREFIX<q>SUFFIX (sim/io/columns.h): "<noun> q label".
struct NumberedLabel {
  const char* prefix;
  const char* suffix;
  const char* noun;
  const char* label;
};
constexpr NumberedLabel kNumberedLabels[] = {
    {"reference", "_mm", "link", "reference deflection [mm]"},
    {"measured", "_mm", "link", "measured deflection [mm]"},
    {"voltage", "_V", "link", "voltage [V]"},
    {"relative", "_mm", "link", "relative tip deflection [mm]"},
    {"free", "_mm", "link", "free tip deflection [mm]"},
    {"tip", "_lateral_mm", "link", "tip lateral position [mm]"},
    {"tip", "_x_mm", "tip", "x [mm]"},
    {"tip", "_y_mm", "tip", "y [mm]"},
    {"y_link", "", "link", "step response [mm]"},
    {"u_link", "", "link", "voltage in the step [V]"},
    {"q_ref", "_rad", "joint", "reference angle [rad]"},
    {"q", "_rad", "joint", "angle [rad]"},
};

// Unit suffixes of names not in the tables, longest first.
constexpr LabelEntry kUnitSuffixes[] = {
    {"_um_per_mm", "um/mm"},
    {"_mm_s2", "mm/s^2"},
    {"_rad_s", "rad/s"},
    {"_kg_m3", "kg/m^3"},
    {"_Pa_s", "Pa s"},
    {"_mm_s", "mm/s"},
    {"_mm", "mm"},
    {"_um", "um"},
    {"_Hz", "Hz"},
    {"_rad", "rad"},
    {"_deg", "deg"},
    {"_db", "dB"},
    {"_V", "V"},
    {"_s", "s"},
};

std::string SpelledOut(std::string name) {
  std::string unit;
  for (const LabelEntry& suffix : kUnitSuffixes) {
    const std::string tail = suffix.column;
    if (name.size() > tail.size() &&
        name.compare(name.size() - tail.size(), tail.size(), tail) == 0) {
      name.erase(name.size() - tail.size());
      unit = suffix.label;
      break;
    }
  }
  std::replace(name.begin(), name.end(), '_', ' ');
  std::replace(name.begin(), name.end(), '.', ' ');
  return unit.empty() ? name : name + " [" + unit + "]";
}

}  // namespace

const std::vector<std::string>& FigureKindNames() {
  static const std::vector<std::string> names = {
      "bode", "step", "tracking", "waveform", "surface", "trajectory", "identification", "sweep"};
  return names;
}

FigureKind FigureKindOf(const std::string& name) {
  const std::vector<std::string>& names = FigureKindNames();
  const auto at = std::find(names.begin(), names.end(), name);
  if (at == names.end()) {
    std::string all;
    for (const std::string& kind : names) all += (all.empty() ? "" : ", ") + kind;
    throw FieldError("plot: unknown figure kind '" + name + "' (kinds: " + all + ")", "kind", all);
  }
  return static_cast<FigureKind>(at - names.begin());
}

void FigureOptions::Validate(FigureKind kind) const {
  const auto fail = [](const std::string& option, const std::string& requirement,
                       const std::string& got) {
    throw FieldError("plot: " + option + " must be " + requirement + ", got " + got, option,
                     requirement);
  };
  if (kind == FigureKind::kBode && curves.empty()) fail("--curves", "non-empty", "nothing");
  if (instants < 1 || instants > kMaxInstants) {
    fail("--instants", "in [1, " + std::to_string(kMaxInstants) + "]", std::to_string(instants));
  }
  for (double t : times_s) {
    if (!std::isfinite(t)) fail("--times-s", "finite", FormatDouble(t));
  }
  if (times_s.size() > static_cast<size_t>(kMaxInstants)) {
    fail("--times-s", "at most " + std::to_string(kMaxInstants) + " times",
         std::to_string(times_s.size()));
  }
  if (!std::isfinite(period_s) || period_s < 0) {
    fail("--period-s", "finite and >= 0 (0: period_s of summary.json)", FormatDouble(period_s));
  }
  if (max_lines < kMinMapRows) {
    fail("--max-lines", ">= " + std::to_string(kMinMapRows), std::to_string(max_lines));
  }
  if (kind == FigureKind::kSweep && (x_column.empty() || y_column.empty())) {
    throw FieldError("plot: plot sweep needs --x and --y", x_column.empty() ? "--x" : "--y",
                     "a column of the sweep table");
  }
}

FigureReport DrawFigureOf(FigureKind kind, const std::string& input, const FigureOptions& options,
                          const std::string& out_path) {
  options.Validate(kind);
  FigureFormatOf(out_path);  // an unknown format stops before anything is read
  const CsvTable table = CsvTable::Read(input);
  FigureScratch scratch;
  FigureReport report;
  using Builder = Figure (*)(const CsvTable&, const std::string&, const FigureOptions&,
                             const FigureScratch&, FigureReport&);
  const Builder builders[] = {BodeFigure,    StepFigure,       TrackingFigure,       WaveformFigure,
                              SurfaceFigure, TrajectoryFigure, IdentificationFigure, SweepFigure};
  const Figure figure = builders[static_cast<int>(kind)](table, input, options, scratch, report);
  DrawFigure(figure, scratch, out_path, input, options.size);
  return report;
}

std::string AxisLabel(const std::string& column) {
  for (const LabelEntry& entry : kLabels) {
    if (column == entry.column) return entry.label;
  }
  // An array element of a sweep table: "link_lengths_mm[0]" -> link 1.
  const size_t open = column.find('[');
  if (open != std::string::npos && column.back() == ']') {
    const std::string base = column.substr(0, open);
    const std::optional<long> index =
        ParseInteger(column.substr(open + 1, column.size() - open - 2));
    if (base == "link_lengths_mm" && index)
      return "link " + std::to_string(*index + 1) + " length [mm]";
    return AxisLabel(base) + " (element " + column.substr(open + 1, column.size() - open - 2) + ")";
  }
  for (const NumberedLabel& entry : kNumberedLabels) {
    const std::string prefix = entry.prefix, suffix = entry.suffix;
    if (column.size() <= prefix.size() + suffix.size() || column.rfind(prefix, 0) != 0 ||
        column.compare(column.size() - suffix.size(), suffix.size(), suffix) != 0) {
      continue;
    }
    const std::optional<long> q =
        ParseInteger(column.substr(prefix.size(), column.size() - prefix.size() - suffix.size()));
    if (q && *q > 0) return std::string(entry.noun) + " " + std::to_string(*q) + " " + entry.label;
  }
  // "link<q>_<result>" of a sweep table.
  if (column.rfind("link", 0) == 0) {
    const size_t underscore = column.find('_');
    const std::optional<long> link = underscore == std::string::npos
                                         ? std::nullopt
                                         : ParseInteger(column.substr(4, underscore - 4));
    if (link) {
      const std::string result = column.substr(underscore + 1);
      for (const LabelEntry& entry : kLinkResultLabels) {
        if (result == entry.column) return "link " + std::to_string(*link) + " " + entry.label;
      }
    }
  }
  return SpelledOut(column);
}

}  // namespace ipmc
