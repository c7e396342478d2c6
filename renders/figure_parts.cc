#include "renders/figure_parts.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "sim/base/error.h"

namespace ipmc::figure_parts {

namespace fs = std::filesystem;

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

// Panels stacked in inches from the top of a canvas `height_in` tall:
// the box of a panel `top_in` below the top, `tall_in` tall.
std::string StackedPanel(double height_in, double top_in, double tall_in, double left,
                         double right) {
  return PanelBox(left, right, 1.0 - (top_in + tall_in) / height_in, 1.0 - top_in / height_in);
}

SteadyCycles SteadyCyclesOf(const std::vector<double>& t_s, double period_s) {
  if (t_s.empty() || !(period_s > 0.0)) return {t_s.empty() ? 0.0 : t_s.front(), "the run"};
  // The samples end a sample short of the last cycle's end.
  const int cycles = static_cast<int>(std::lround((t_s.back() - t_s.front()) / period_s));
  if (cycles < 2) return {t_s.front(), "the run"};
  return {t_s.front() + period_s,
          cycles == 2 ? "cycle 2" : "cycles 2-" + std::to_string(cycles)};
}

double RmsError(const std::vector<double>& t_s, const std::vector<double>& reference,
                const std::vector<double>& measured, double from_s) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t i = 0; i < t_s.size(); ++i) {
    if (t_s[i] < from_s - 1e-9 * std::abs(from_s)) continue;
    const double error = measured[i] - reference[i];
    sum += error * error;
    ++count;
  }
  return count ? std::sqrt(sum / count) : NAN;
}

std::vector<ClampInterval> ClampIntervals(const std::vector<double>& time_s,
                                          const std::vector<double>& voltage, bool clamp,
                                          double v_max) {
  std::vector<ClampInterval> intervals;
  const std::size_t n = std::min(time_s.size(), voltage.size());
  const auto at_clamp = [&](std::size_t i) {
    return std::abs(voltage[i]) >= v_max * (1.0 - 1e-9);
  };
  const auto half_way = [&](std::size_t a, std::size_t b) { return 0.5 * (time_s[a] + time_s[b]); };
  for (std::size_t i = 0; clamp && i < n;) {
    if (!at_clamp(i)) {
      ++i;
      continue;
    }
    std::size_t last = i;
    while (last + 1 < n && at_clamp(last + 1)) ++last;
    intervals.push_back({i == 0 ? time_s[0] : half_way(i - 1, i),
                         last + 1 == n ? time_s[last] : half_way(last, last + 1), last - i + 1});
    i = last + 1;
  }
  return intervals;
}

}  // namespace ipmc::figure_parts
