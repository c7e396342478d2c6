// The compare figure: several runs' outputs overlaid, one colour per run,
// named in the legend by what differs between their resolved scenarios.
#include "renders/figure_parts.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/io/toml.h"

namespace ipmc::figure_parts {
namespace {

namespace fs = std::filesystem;

// At most this many differing keys name a run in the legend.
constexpr size_t kMaxLegendKeys = 3;

struct ComparedRun {
  std::string dir;
  nlohmann::json summary;
  CsvTable table;
  std::map<std::string, std::string> settings;  // dotted key -> value as text
  std::string label;
};

// A TOML value as the legend shows it: numbers as the shortest text that
// reads back exactly (5e-4 s, not 0.00050000000000000001), arrays
// element by element.
std::string ValueText(const toml::node& node) {
  if (const auto* text = node.as_string()) return text->get();
  if (const auto* integer = node.as_integer()) return std::to_string(integer->get());
  if (const auto* number = node.as_floating_point()) return FormatShortest(number->get());
  if (const auto* boolean = node.as_boolean()) return boolean->get() ? "true" : "false";
  if (const toml::array* array = node.as_array()) {
    std::string joined;
    for (const toml::node& element : *array) {
      joined += (joined.empty() ? "" : ", ") + ValueText(element);
    }
    return "[" + joined + "]";
  }
  std::ostringstream value;
  node.visit([&value](const auto& leaf) { value << leaf; });
  return value.str();
}

void Flatten(const toml::table& table, const std::string& prefix,
             std::map<std::string, std::string>& out) {
  for (const auto& [key, node] : table) {
    const std::string name = prefix + std::string(key.str());
    if (const toml::table* inner = node.as_table()) {
      Flatten(*inner, name + ".", out);
    } else {
      out[name] = ValueText(node);
    }
  }
}

// What the run was set up with: its resolved scenario's keys (a model by
// its file name), or, for a run without one (a gait), its summary's
// inputs and gait.
std::map<std::string, std::string> SettingsOf(const nlohmann::json& summary,
                                              const std::string& source) {
  std::map<std::string, std::string> settings;
  const nlohmann::json& inputs = summary.contains("inputs") ? summary["inputs"] : summary;
  const std::string resolved = JsonText(inputs, "resolved_scenario");
  if (!resolved.empty()) {
    Flatten(ParseToml(resolved, source + " (inputs.resolved_scenario)"), "", settings);
  } else if (inputs.is_object()) {
    for (const auto& [key, value] : inputs.items()) {
      if (key == "program_version" || key == "model_sha256") continue;
      settings[key] = value.is_string() ? value.get<std::string>() : value.dump();
    }
    if (!JsonText(summary, "gait").empty()) settings["gait"] = JsonText(summary, "gait");
  }
  if (settings.count("model")) settings["model"] = fs::path(settings["model"]).filename().string();
  return settings;
}

// The keys whose values are not the same in every run; a table whose kind
// differs stands for its other keys ("controller.kind" and not
// "controller.kp").
std::vector<std::string> DifferingKeys(const std::vector<ComparedRun>& runs) {
  std::set<std::string> keys;
  for (const ComparedRun& run : runs) {
    for (const auto& entry : run.settings) keys.insert(entry.first);
  }
  std::vector<std::string> differing;
  for (const std::string& key : keys) {
    const auto value = [&](const ComparedRun& run) {
      const auto at = run.settings.find(key);
      return at == run.settings.end() ? std::string("\x01") : at->second;
    };
    const bool same = std::all_of(runs.begin(), runs.end(), [&](const ComparedRun& run) {
      return value(run) == value(runs.front());
    });
    if (!same) differing.push_back(key);
  }
  std::vector<std::string> kept;
  for (const std::string& key : differing) {
    const size_t dot = key.rfind('.');
    const std::string kind = dot == std::string::npos ? "kind" : key.substr(0, dot) + ".kind";
    const bool covered = key != kind && std::find(differing.begin(), differing.end(), kind) !=
                                            differing.end();
    if (!covered) kept.push_back(key);
  }
  return kept;
}

std::string LabelOf(const ComparedRun& run, const std::vector<std::string>& differing) {
  std::string label;
  size_t shown = 0;
  for (const std::string& key : differing) {
    const auto at = run.settings.find(key);
    if (at == run.settings.end()) continue;
    if (shown == kMaxLegendKeys) {
      label += ", ...";
      break;
    }
    label += (label.empty() ? "" : ", ") + key + " = " + at->second;
    ++shown;
  }
  return label.empty() ? fs::path(run.dir).lexically_normal().filename().string() : label;
}

ComparedRun ReadRun(const std::string& dir) {
  const fs::path timeseries = fs::path(dir) / "timeseries.csv";
  const fs::path summary_path = fs::path(dir) / "summary.json";
  for (const fs::path& path : {timeseries, summary_path}) {
    if (!fs::is_regular_file(path)) {
      throw InputError(InputProblem::kMissing, {dir}, "",
                       "not a run's output directory (no " + path.filename().string() + ")");
    }
  }
  const nlohmann::json summary = SideJson(timeseries.string(), "summary.json");
  if (summary.is_null()) {
    throw InputError(InputProblem::kSyntax, {summary_path.string()}, "", "not a JSON object");
  }
  ComparedRun run{dir, summary, CsvTable::Read(timeseries.string()), {}, ""};
  RequireRows(run.table, 2);
  run.table.Column(columns::kTime);
  run.table.Column(columns::kComX);
  run.settings = SettingsOf(summary, summary_path.string());
  return run;
}

int LinksOf(const CsvTable& table) {
  int links = 0;
  while (table.Has(columns::Reference(links + 1)) && table.Has(columns::Measured(links + 1))) {
    ++links;
  }
  return links;
}

// One line per run of a panel, `column` of that run's data file: the
// first run wide and solid, the others narrower and dashed, so that
// curves on top of each other stay apart.
std::string RunLines(const std::vector<std::string>& data, int column, bool titled,
                     const std::vector<ComparedRun>& runs, const char* style = "lines") {
  std::string plot = "plot ";
  bool first = true;
  for (size_t k = 0; k < runs.size(); ++k) {
    if (data[k].empty()) continue;
    plot += (first ? "" : ", ") + data[k] + " using 1:" + std::to_string(column) + " with " +
            style + (k == 0 ? " lw 3 dt 1" : " lw 1.6 dt " + std::to_string(1 + k)) +
            " pt 7 ps 0.8 lc " + Rgb(kSeries[k % kSeriesCount]) + " " +
            (titled ? "title " + Q(runs[k].label) : std::string("notitle"));
    first = false;
  }
  return plot + "\n";
}

// A y axis for values within [low, high] with about four tics and the top
// `reserved` fraction of the panel left free (for labels).
std::string YAxis(double low, double high, double reserved = 0.0) {
  if (!(high > low)) {
    low -= 1.0;
    high += 1.0;
  }
  const double pad = 0.08 * (high - low);
  low -= pad;
  high += pad;
  const double top = low + (high - low) / (1.0 - reserved);
  return "set yrange [" + N(low) + ":" + N(top) + "]\nset ytics " +
         N(NiceStep(high - low, 4)) + "\n";
}

// The smallest and largest finite value seen.
struct Span {
  double low = INFINITY, high = -INFINITY;
  void Add(const std::vector<double>& values) {
    for (double v : values) {
      if (!std::isfinite(v)) continue;
      low = std::min(low, v);
      high = std::max(high, v);
    }
  }
};

// The page's rows [in]: each panel's height, the gap between rows and the
// time axis below the first row; its columns (the fraction of its width):
// the displacement and errors left, the cycles and voltages right.
constexpr double kRow = 1.75, kRowGap = 0.45, kAxisGap = 0.4;
constexpr double kLeft0 = 0.08, kRight0 = 0.49, kLeft1 = 0.585, kRight1 = 0.975;

// Per run its data files (time, displacement along the axis, per link
// error and voltage; its cycles), its RMS tracking error per link over its
// steady cycles, and each column's span over every run.
struct ComparedSeries {
  std::vector<std::string> series, cycles;
  std::vector<std::vector<double>> steady_rms;
  std::string steady_what;
  // Column c's span over every run (c as in the data files, from 1), and
  // the per-cycle displacements'.
  std::vector<Span> spans;
  Span cycle_span;
};

// Writes the runs' data files into `scratch` and one note per run into `report`.
ComparedSeries WriteComparedSeries(const std::vector<ComparedRun>& runs, int links,
                                   const FigureScratch& scratch, FigureReport& report) {
  ComparedSeries data;
  data.series.resize(runs.size());
  data.cycles.resize(runs.size());
  data.steady_rms.resize(runs.size());
  data.spans.resize(3 + 2 * links);
  std::vector<std::string>& series = data.series;
  std::vector<std::string>& cycles = data.cycles;
  std::vector<std::vector<double>>& steady_rms = data.steady_rms;
  std::string& steady_what = data.steady_what;
  std::vector<Span>& spans = data.spans;
  Span& cycle_span = data.cycle_span;
  for (size_t k = 0; k < runs.size(); ++k) {
    const CsvTable& table = runs[k].table;
    const std::vector<double> t = table.Numbers(columns::kTime);
    const std::vector<double> com_x = table.Numbers(columns::kComX);
    std::vector<std::vector<double>> columns_out = {t, std::vector<double>(t.size())};
    for (size_t i = 0; i < t.size(); ++i) columns_out[1][i] = -(com_x[i] - com_x[0]);
    const SteadyCycles steady = SteadyCyclesOf(t, JsonNumber(runs[k].summary, "period_s", 0.0));
    if (k == 0) steady_what = steady.what;
    if (steady.what != steady_what) steady_what = "their steady cycles";
    for (int q = 1; q <= links; ++q) {
      std::vector<double> error(t.size(), NAN), voltage(t.size(), NAN);
      if (table.Has(columns::Reference(q)) && table.Has(columns::Measured(q))) {
        const std::vector<double> reference = table.Numbers(columns::Reference(q));
        const std::vector<double> measured = table.Numbers(columns::Measured(q));
        for (size_t i = 0; i < t.size(); ++i) error[i] = measured[i] - reference[i];
        steady_rms[k].push_back(RmsError(t, reference, measured, steady.from_s));
      } else {
        steady_rms[k].push_back(NAN);
      }
      if (table.Has(columns::Voltage(q))) voltage = table.Numbers(columns::Voltage(q));
      columns_out.push_back(error);
      columns_out.push_back(voltage);
    }
    for (size_t c = 1; c < columns_out.size(); ++c) spans[c + 1].Add(columns_out[c]);
    series[k] = scratch.Data("run" + std::to_string(k) + ".dat", GnuplotTable(columns_out));
    std::string rows;
    const nlohmann::json& per_cycle = runs[k].summary.contains("per_cycle")
                                          ? runs[k].summary["per_cycle"]
                                          : nlohmann::json::array();
    for (const nlohmann::json& cycle : per_cycle) {
      cycle_span.Add({JsonNumber(cycle, "com_along_mm", NAN)});
      rows += GnuplotValue(JsonNumber(cycle, "cycle", NAN)) + " " +
              GnuplotValue(JsonNumber(cycle, "com_along_mm", NAN)) + "\n";
    }
    if (!rows.empty()) cycles[k] = scratch.Data("cycles" + std::to_string(k) + ".dat", rows);
    std::string note = "run " + std::to_string(k + 1) + " (" + runs[k].label + ")";
    if (!per_cycle.empty()) {
      note += ": last cycle " + Format("%.6g", JsonNumber(per_cycle.back(), "com_along_mm", NAN)) +
              " mm along";
    }
    if (links > 0) {
      note += "; RMS tracking error over " + steady.what + ", per link";
      for (size_t q = 0; q < steady_rms[k].size(); ++q) {
        note += (q ? ", " : " ") + Format("%.4g", steady_rms[k][q]);
      }
      note += " mm";
    }
    report.notes.push_back(note);
  }
  return data;
}

// The panels of links 1..links below the displacement's, each the error
// and the voltage of every run, from the top `head_in` of a figure
// `height_in` high.
std::string LinkPanels(const std::vector<ComparedRun>& runs, int links, const ComparedSeries& data,
                       double height_in, double head_in) {
  const double H = height_in, kHead = head_in;
  const std::vector<std::string>& series = data.series;
  const std::vector<Span>& spans = data.spans;
  const std::string time_label = Q(AxisLabel(columns::kTime));
  std::string commands;
  for (int q = 1; q <= links; ++q) {
    const double top = kHead + q * (kRow + kRowGap) + kAxisGap;
    const bool last = q == links;
    const std::string x_axis = last ? "set format x '%g'\nset xlabel " + time_label +
                                          " offset 0,0.3\n"
                                    : std::string("set format x ''\nunset xlabel\n");
    std::string rms_labels;
    for (size_t k = 0; k < runs.size(); ++k) {
      const double rms = data.steady_rms[k][q - 1];
      if (!std::isfinite(rms)) continue;
      rms_labels += "set label " + std::to_string(k + 1) + " " +
                    Q("RMS over " + data.steady_what + ": " + Format("%.4g", rms) + " mm") +
                    " at graph 0.02, graph " + N(0.9 - 0.11 * static_cast<double>(k)) +
                    " left front boxed textcolor " + Rgb(kSeries[k % kSeriesCount]) + "\n";
    }
    commands += StackedPanel(H, top, kRow, kLeft0, kRight0) + x_axis + "set title " +
                Q("link " + std::to_string(q) + ": tracking error, measured - reference") +
                " offset 0,-0.4\nset ylabel 'error [mm]'\n" + rms_labels +
                YAxis(spans[1 + 2 * q].low, spans[1 + 2 * q].high,
                      0.1 + 0.11 * static_cast<double>(runs.size())) +
                RunLines(series, 1 + 2 * q, false, runs) + "unset label\n" +
                StackedPanel(H, top, kRow, kLeft1, kRight1) + "set title " +
                Q("link " + std::to_string(q) + ": voltage") +
                " offset 0,-0.4\nset ylabel 'voltage [V]'\n" +
                YAxis(spans[2 + 2 * q].low, spans[2 + 2 * q].high) + RunLines(series, 2 + 2 * q, false, runs);
  }
  return commands;
}

}  // namespace

Figure CompareFigure(const std::vector<std::string>& run_dirs, const FigureOptions& options,
                     const FigureScratch& scratch, FigureReport& report) {
  std::vector<ComparedRun> runs;
  for (const std::string& dir : run_dirs) runs.push_back(ReadRun(dir));
  const std::vector<std::string> differing = DifferingKeys(runs);
  if (!options.labels.empty() && options.labels.size() != runs.size()) {
    throw FieldError("plot: --labels gives " + std::to_string(options.labels.size()) +
                         " labels for " + std::to_string(runs.size()) + " runs (one per run)",
                     "--labels", "one label per run directory");
  }
  for (size_t k = 0; k < runs.size(); ++k) {
    runs[k].label = options.labels.empty() ? LabelOf(runs[k], differing) : options.labels[k];
  }
  int links = LinksOf(runs.front().table);
  for (const ComparedRun& run : runs) links = std::max(links, LinksOf(run.table));

  const ComparedSeries data = WriteComparedSeries(runs, links, scratch, report);
  const std::vector<std::string>& series = data.series;
  const std::vector<std::string>& cycles = data.cycles;
  const std::vector<Span>& spans = data.spans;
  const Span& cycle_span = data.cycle_span;

  std::string differs;
  for (const std::string& key : differing) differs += (differs.empty() ? "" : ", ") + key;
  SetTitle(report, options, "Comparison of " + std::to_string(runs.size()) + " runs",
           differing.empty() ? "the same scenario" : "differing in " + differs);

  // Inches: title and legend, the displacement row, then a row per link.
  // The first row has its own time axis below it.
  // The head holds the title and, below it, the legend: one run per line,
  // so that no label runs off the page or over a panel's title.
  constexpr double kTitle = 0.75, kLegendLine = 0.2, kLegendGap = 0.5;
  const double kHead = kTitle + kLegendLine * static_cast<double>(runs.size()) + kLegendGap;
  constexpr double kFoot = 0.55;
  Figure figure;
  figure.width_in = 10.0;
  figure.height_in = kHead + (1 + links) * (kRow + kRowGap) - kRowGap + kAxisGap * (links > 0) + kFoot;
  const double H = figure.height_in;
  const std::string time_label = Q(AxisLabel(columns::kTime));
  std::string commands = "set multiplot title " + Heading(report) + "\n" +
                         "set key at screen " + N(kLeft0) + ", screen " + N(1.0 - kTitle / H) +
                         " left top vertical reverse Left samplen 4 maxcols 1 spacing 1.1\n"
                         "set style textbox opaque noborder margins 2, 1\n";
  commands += StackedPanel(H, kHead, kRow, kLeft0, kRight0) +
              "set title 'centre of mass: displacement along the swimming axis' offset 0,-0.4\n"
              "set xlabel " +
              time_label + " offset 0,0.3\nset ylabel 'displacement [mm]'\n" +
              YAxis(spans[2].low, spans[2].high) + RunLines(series, 2, true, runs) +
              "set key off\n";
  bool any_cycles = false;
  for (const std::string& cycle_file : cycles) any_cycles = any_cycles || !cycle_file.empty();
  if (any_cycles) {
    commands += StackedPanel(H, kHead, kRow, kLeft1, kRight1) +
                "set title 'displacement per cycle (summary.json)' offset 0,-0.4\n"
                "set xlabel 'cycle' offset 0,0.3\nset ylabel 'along the axis [mm]'\n"
                "set xtics 1\nset offsets 0.25, 0.25, 0, 0\n" +
                YAxis(cycle_span.low, cycle_span.high) + RunLines(cycles, 2, false, runs, "linespoints") +
                "set xtics autofreq\nset offsets 0, 0, 0, 0\n";
  }
  commands += LinkPanels(runs, links, data, H, kHead);
  figure.commands = commands + "unset multiplot\n";
  return figure;
}

}  // namespace ipmc::figure_parts
