// A sweep table's --y against --x, one curve per --group.
#include "renders/figure_parts.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/runs/run_warnings.h"

namespace ipmc::figure_parts {
namespace {

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

// A logarithmic x axis over less than a decade or two gets few or no
// labelled tics of gnuplot's own (1, 10, ...): a tic at each swept value
// instead, when there are at most 12.
std::string LogTicsAtValues(
    const std::map<std::string, std::vector<std::pair<double, double>>>& points) {
  std::set<double> values;
  for (const auto& [group, curve] : points) {
    for (const auto& point : curve) values.insert(point.first);
  }
  if (values.empty() || values.size() > 12) return "";
  std::string tics;
  for (double value : values) {
    tics += (tics.empty() ? "set xtics (" : ", ") + Q(GnuplotValue(value)) + " " +
            GnuplotValue(value);
  }
  return tics + ")\n";
}

// A logarithmic y axis over the data's own range, 5 % (of its decades)
// beyond each end, rather than gnuplot's whole decades around it (0.001
// to 10 for data in 0.045-0.66), and tics at 1, 2 and 5 of each decade
// when it spans less than two; "" without positive values.
std::string LogYRange(const std::map<std::string, std::vector<std::pair<double, double>>>& points) {
  double low = INFINITY, high = 0.0;
  for (const auto& [group, curve] : points) {
    for (const auto& point : curve) {
      if (point.second > 0.0 && std::isfinite(point.second)) {
        low = std::min(low, point.second);
        high = std::max(high, point.second);
      }
    }
  }
  if (!(high > 0.0) || !std::isfinite(low)) return "";
  const double decades = std::max(std::log10(high / low), 0.3);
  const double pad = std::pow(10.0, 0.05 * decades);
  std::string commands = "set yrange [" + GnuplotValue(low / pad) + ":" +
                         GnuplotValue(high * pad) + "]\n";
  if (decades < 2.0) {
    std::string tics;
    for (int e = static_cast<int>(std::floor(std::log10(low / pad)));
         e <= static_cast<int>(std::ceil(std::log10(high * pad))); ++e) {
      for (double m : {1.0, 2.0, 5.0}) {
        const double tic = e < 0 ? m / std::pow(10.0, -e) : m * std::pow(10.0, e);
        if (tic < low / pad || tic > high * pad) continue;
        tics += (tics.empty() ? "set ytics (" : ", ") + Q(FormatShortest(tic)) + " " +
                GnuplotValue(tic);
      }
    }
    if (!tics.empty()) commands += tics + ")\n";
  }
  return commands;
}

}  // namespace

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
  // The points whose runs warn (sim/runs/run_warnings.h), circled.
  std::vector<std::pair<double, double>> warned;
  std::vector<std::vector<std::string>> plotted;
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
    if (!FailedChecks(table.columns(), table.Row(r)).empty()) {
      warned.push_back({x, table.Number(r, y_column)});
    }
    plotted.push_back(table.Row(r));
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
  if (options.log_y) commands += "set logscale y\nset autoscale yfix\n" + LogYRange(points);
  if (!numeric_x) {
    commands += "set xrange [-0.5:" + N(categories.size() - 0.5) + "]\nset xtics (";
    for (size_t k = 0; k < categories.size(); ++k) {
      commands += (k ? ", " : "") + Q(categories[k]) + " " + std::to_string(k);
    }
    commands += ")\n";
  } else {
    // The x range ends 3 % beyond the data, not at the next tic beyond that.
    commands += "set autoscale xfix\nset offsets graph 0.03, graph 0.03, graph 0.05, graph 0.05\n";
    if (options.log_x) commands += LogTicsAtValues(points);
  }
  // Numeric group values carry the group column's unit in the key, or,
  // without one, its name: "start 0", not a bare "0".
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
    std::string label = AxisLabel(options.y_column);
    if (grouped) {
      const bool numeric = ParseDouble(groups[k]).has_value();
      label = !numeric              ? groups[k]
              : group_unit.empty() ? WithoutUnit(AxisLabel(options.group_column)) + " " + groups[k]
                                   : groups[k] + group_unit;
    }
    plot += (k ? ", " : "") + data + " index " + std::to_string(k) + " using 1:2 with " +
            (numeric_x ? "linespoints lw 2" : "points") + " pt 7 ps 1.1 lc " +
            Rgb(kSeries[k % kSeriesCount]) + " title " + Q(label);
  }
  if (!warned.empty()) {
    // The key names how many; the notes (printed) say for what.
    const std::string counts = WarningCountsText(table.columns(), plotted);
    std::string circled;
    for (const auto& [x, y] : warned) circled += GnuplotValue(x) + " " + GnuplotValue(y) + "\n";
    plot += ", " + scratch.Data("warned.dat", circled) +
            " using 1:2 with points pt 6 ps 3.2 lw 2 lc rgb '#c00000' title " +
            Q("circled: " + counts.substr(0, counts.find(':')));
    report.notes.push_back(counts + " (circled)");
  }
  Figure figure;
  figure.width_in = 7.0;
  figure.height_in = 5.0;
  figure.commands = commands + plot + "\n";
  return figure;
}

}  // namespace ipmc::figure_parts
