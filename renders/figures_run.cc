// Figures of a run's timeseries.csv: tracking (Fig. 12a), waveform (Fig. 12b),
// surface (Fig. 13) and trajectory; the body in the head's frame comes from
// sim/runs/body_record.h.
#include "renders/figure_parts.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "renders/swim_film.h"  // ScenarioIdealShape
#include "sim/core/scenario.h"
#include "sim/runs/body_record.h"
#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/base/error.h"
#include "sim/base/numbers.h"

namespace ipmc::figure_parts {
namespace {

constexpr int kMapColumns = 91;  // x samples along the body in the x-t map

// -------------------------------------------------------------- tracking ---

std::vector<int> Numbered(const CsvTable& table, std::string (*column)(int)) {
  std::vector<int> found;
  for (int q = 1; table.Has(column(q)); ++q) found.push_back(q);
  return found;
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

// A link's largest |deflection| [mm], and its error panel's y axis, which
// leaves its top fifth to the RMS, with no tic there (a tic at the top
// would touch the panel above).
struct TrackingAxes {
  double deflection_max_mm = 0.0;
  std::string error_axis;
};

TrackingAxes TrackingAxesOf(const std::vector<double>& reference,
                            const std::vector<double>& measured) {
  double deflection_max = 0.0, error_max = 0.0;
  for (size_t i = 0; i < reference.size(); ++i) {
    deflection_max = std::max({deflection_max, std::abs(reference[i]), std::abs(measured[i])});
    if (std::isfinite(measured[i] - reference[i])) {
      error_max = std::max(error_max, std::abs(measured[i] - reference[i]));
    }
  }
  if (!(error_max > 0.0)) error_max = 1e-3;
  const double error_step = NiceStep(2.2 * error_max, 4);
  const double error_tic = error_step * std::max(1.0, std::floor(1.1 * error_max / error_step));
  const std::string error_axis = "set yrange [" + N(-1.1 * error_max) + ":" +
                                 N(1.1 * error_max + 0.5 * error_max) + "]\nset ytics " +
                                 N(-error_tic) + ", " + N(error_step) + ", " + N(error_tic) + "\n";
  return {deflection_max, error_axis};
}

// Closed loop: per link, deflection above and voltage below.
Figure LinkTrackingFigure(const CsvTable& table, const std::vector<int>& links,
                          const nlohmann::json& summary, const FigureScratch& scratch,
                          const std::string& heading, FigureReport& report) {
  const bool clamp = summary.contains("clamp_enabled") && summary["clamp_enabled"].is_boolean() &&
                     summary["clamp_enabled"].get<bool>();
  const double v_max = JsonNumber(summary, "v_max_V", 0.0);
  const std::vector<double> t = table.Numbers(columns::kTime);
  const int n = static_cast<int>(links.size());
  // The error's RMS over the steady cycles (after the first, whose start
  // ramp and transient are not steady).
  const SteadyCycles steady = SteadyCyclesOf(t, JsonNumber(summary, "period_s", 0.0));
  // Inches: title and key, then per link its heading, deflection, error
  // and voltage panels, then the time axis.
  constexpr double kHead = 1.05, kLinkHeading = 0.3, kDeflection = 1.35, kGap = 0.06,
                   kError = 0.8, kVoltage = 0.9,
                   kBlock = kLinkHeading + kDeflection + kGap + kError + kGap + kVoltage + 0.12,
                   kFoot = 0.5;
  // The panels' left edge, with room for the error's tick labels.
  constexpr double kLeft = 0.14;
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
    const std::vector<ClampInterval> at_clamp = ClampIntervals(t, voltage, clamp, v_max);
    size_t clamped_samples = 0;
    std::vector<double> clamp_start, clamp_end;
    for (const ClampInterval& interval : at_clamp) {
      clamped_samples += interval.samples;
      clamp_start.push_back(interval.start_s);
      clamp_end.push_back(interval.end_s);
    }
    const std::string data = scratch.Data("tracking" + std::to_string(q) + ".dat",
                                          GnuplotTable({t, reference, measured, voltage}));
    // One box per interval at the clamp, from -1.2 to 1.2 V_max.
    const std::string shade =
        at_clamp.empty()
            ? std::string()
            : scratch.Data("clamp" + std::to_string(q) + ".dat",
                           GnuplotTable({clamp_start, clamp_end})) +
                  " using (($1 + $2) / 2):(0):(($2 - $1) / 2):(" + N(1.2 * v_max) +
                  ") with boxxyerror fs solid 1.0 noborder fc " + Rgb(kClampShade) + " notitle, ";
    const double top = kHead + k * kBlock;
    const bool last = k + 1 == n;
    std::string panel_title = "link " + std::to_string(q);
    if (clamp) {
      // The run's own fraction (every step, summary.json) if it is there,
      // else that of the recorded samples.
      const double fraction =
          LinkSummaryNumber(summary, q, "clamped_fraction")
              .value_or(static_cast<double>(clamped_samples) / std::max<size_t>(1, t.size()));
      panel_title += Format(": voltage at the clamp %.1f %% of the time", 100.0 * fraction);
    }
    const TrackingAxes axes = TrackingAxesOf(reference, measured);
    const double rms = RmsError(t, reference, measured, steady.from_s);
    const std::string rms_text =
        "RMS over " + steady.what + ": " + Format("%.4g", rms) + " mm";
    report.notes.push_back("link " + std::to_string(q) + ": tracking error " + rms_text);
    commands += StackedPanel(H, top + kLinkHeading, kDeflection, kLeft) + "set title " + Q(panel_title) +
                " offset 0,-0.4\nset format x ''\nunset xlabel\n"
                "set ylabel 'deflection [mm]'\nset ytics " +
                N(NiceStep(2.0 * axes.deflection_max_mm, 4)) + "\nset key at screen 0.545, screen " +
                key_y + " center top horizontal maxrows 1 samplen 4\n" + "plot " + data +
                " using 1:2 with lines lw 2 dt 2 lc rgb 'black' " +
                (k == 0 ? "title 'reference'" : "notitle") +
                ", '' using 1:3 with lines lw 1.6 lc " + Rgb(kBlue) + " " +
                (k == 0 ? "title 'measured'" : "notitle") +
                "\n" + "unset title\n" + StackedPanel(H, top + kLinkHeading + kDeflection + kGap, kError, kLeft) +
                "set ylabel 'error [mm]'\nset key off\n" + axes.error_axis +
                "set style textbox opaque noborder margins 2, 1\nset label 1 " +
                Q("measured - reference; " + rms_text) +
                " at graph 0.01, graph 0.86 left front boxed textcolor " + Rgb(kGreen) + "\n" +
                "plot 0 with lines lc rgb 'gray50' notitle, " + data +
                " using 1:($3 - $2) with lines lw 1.4 lc " + Rgb(kGreen) +
                " notitle\nunset label 1\nset autoscale y\nset ytics autofreq\nset key on\n" +
                StackedPanel(H, top + kLinkHeading + kDeflection + kGap + kError + kGap, kVoltage,
                             kLeft) +
                (last ? "set format x '%g'\nset xlabel " + Q(AxisLabel(columns::kTime)) + "\n"
                      : std::string()) +
                "set ylabel 'voltage [V]'\n"
                "set key at screen 0.545, screen " +
                voltage_key_y + " center top horizontal maxrows 1 samplen 4\n" +
                (clamp ? "set yrange [" + N(-1.2 * v_max) + ":" + N(1.2 * v_max) + "]\nset ytics " +
                             N(v_max / 2) + "\n"
                       : std::string("set autoscale y\n")) +
                "plot " +
                (clamp ? shade +
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

}  // namespace

Figure TrackingFigure(const CsvTable& table, const std::string& input, const FigureOptions& options,
                      const FigureScratch& scratch, FigureReport& report) {
  RequireRows(table, 2);
  const nlohmann::json summary = SideJson(input, "summary.json");
  const std::vector<int> links = Numbered(table, &columns::Reference);
  if (!links.empty()) {
    SetTitle(report, options, "Tracking of each link's relative tip deflection",
             RunDescription(summary));
    return LinkTrackingFigure(table, links, summary, scratch, Heading(report), report);
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

namespace {

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

std::string PointsBlock(const std::vector<BodyPoint>& points) {
  std::string text;
  for (const BodyPoint& p : points) text += GnuplotValue(p.x) + " " + GnuplotValue(p.y) + "\n";
  return text;
}

}  // namespace

namespace {

// The scenario's continuous travelling wave y(x, t) [mm] in the head's
// frame (Table 4's for the paper's scenario; faded in as the references
// are), from summary.json's resolved scenario; empty for a run without one
// (a gait) or whose scenario does not read back.
std::function<double(double, double)> ContinuousWave(const nlohmann::json& summary,
                                                     const std::string& input,
                                                     FigureReport& report) {
  const nlohmann::json inputs =
      summary.is_object() && summary.contains("inputs") ? summary["inputs"] : nlohmann::json();
  const std::string resolved = JsonText(inputs, "resolved_scenario");
  if (resolved.empty()) return {};
  try {
    const std::function<double(double, double)> y_m = ScenarioIdealShape(
        ParseScenario(resolved, input + " (summary.json inputs.resolved_scenario)"));
    return [y_m](double x_mm, double t_s) { return 1e3 * y_m(1e-3 * x_mm, t_s); };
  } catch (const std::exception& error) {
    report.notes.push_back(std::string("no continuous wave: ") + error.what());
    return {};
  }
}

}  // namespace

Figure WaveformFigure(const CsvTable& table, const std::string& input, const FigureOptions& options,
                      const FigureScratch& scratch, FigureReport& report) {
  const nlohmann::json summary = SideJson(input, "summary.json");
  const BodyRecord body = ReadBodyRecord(table);
  const bool with_ideal = !body.ideal.empty();
  const std::function<double(double, double)> wave =
      with_ideal ? ContinuousWave(summary, input, report) : nullptr;
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
  // Per instant three blocks: realised, projected onto the links, and the
  // continuous wave over the body's reach along x.
  constexpr int kWavePoints = 121;
  std::string text;
  double x_low = 0.0, x_high = 0.0, y_max = 0.0;
  for (size_t sample : instants) {
    std::string continuous = "NaN NaN\n";
    if (wave) {
      continuous.clear();
      const double reach = body.realised[sample].back().x;
      for (int c = 0; c < kWavePoints; ++c) {
        const double x = reach * c / (kWavePoints - 1);
        const double y = wave(x, body.t_s[sample]);
        y_max = std::max(y_max, std::abs(y));
        continuous += GnuplotValue(x) + " " + GnuplotValue(y) + "\n";
      }
    }
    text += PointsBlock(body.realised[sample]) + "\n\n" +
            (with_ideal ? PointsBlock(body.ideal[sample]) : std::string("NaN NaN\n")) + "\n\n" +
            continuous + "\n\n";
    for (const auto* shapes : {&body.realised, &body.ideal}) {
      if (shapes->empty()) continue;
      for (const BodyPoint& p : (*shapes)[sample]) {
        x_low = std::min(x_low, p.x);
        x_high = std::max(x_high, p.x);
        y_max = std::max(y_max, std::abs(p.y));
      }
    }
  }
  const std::string data = scratch.Data("waveform.dat", text);
  SetTitle(report, options,
           wave        ? "Body shape in the head's frame: the wave, its projection onto the links, "
                         "realised"
           : with_ideal ? "Body shape in the head's frame, ideal and realised"
                        : "Body shape in the head's frame",
           RunDescription(summary));
  std::string plot = "plot ";
  for (size_t k = 0; k < instants.size(); ++k) {
    const std::string colour = Rgb(kSeries[k % kSeriesCount]);
    const std::string block = std::to_string(3 * k);
    plot += (k ? ", " : "") + data + " index " + block +
            " using 1:2 with linespoints lw 2 pt 7 ps 0.9 lc " + colour + " title " +
            Q(Format("t = %.4g s", body.t_s[instants[k]]));
    if (with_ideal) {
      plot += ", '' index " + std::to_string(3 * k + 1) +
              " using 1:2 with linespoints lw 1.5 dt 2 pt 6 ps 0.9 lc " + colour + " notitle";
    }
    if (wave) {
      plot += ", '' index " + std::to_string(3 * k + 2) + " using 1:2 with lines lw 1.2 dt 3 lc " +
              colour + " notitle";
    }
  }
  if (with_ideal) {
    plot += ", NaN with lines lw 2 lc rgb 'black' title 'realised', NaN with lines lw 1.5 "
            "dt 2 lc rgb 'black' title " +
            Q(wave ? "projected onto the links" : "ideal (dashed)");
  }
  if (wave) {
    plot += ", NaN with lines lw 1.2 dt 3 lc rgb 'black' title 'wave y(x, t)'";
  }
  const double margin = 0.03 * (x_high - x_low);
  Figure figure;
  figure.width_in = 7.5;
  figure.height_in = 4.6;
  figure.commands = "set title " + Heading(report) + "\n" +
                    "set xlabel 'x along the body from the head [mm]' offset 0,0.4\n"
                    "set ylabel 'y lateral [mm]'\n"
                    "set xrange [" +
                    N(x_low - margin) + ":" + N(x_high + margin) + "]\n" + "set yrange [" +
                    N(-1.15 * std::max(y_max, 1e-3)) + ":" + N(1.15 * std::max(y_max, 1e-3)) +
                    "]\n" +
                    "set key outside bottom center horizontal maxcols 4 samplen 3 spacing 1.1 width -2\n"
                    "set xzeroaxis lt 1 lc rgb 'gray40'\n" +
                    plot + "\n";
  return figure;
}

namespace {

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

// The length of the polyline.
double ArcLength(const std::vector<BodyPoint>& shape) {
  double length = 0.0;
  for (size_t k = 0; k + 1 < shape.size(); ++k) {
    length += std::hypot(shape[k + 1].x - shape[k].x, shape[k + 1].y - shape[k].y);
  }
  return length;
}

// y of the point at distance s along the polyline from its first point
// (linear between its points); its last point's y beyond its end.
double LateralAlong(const std::vector<BodyPoint>& shape, double s) {
  double walked = 0.0;
  for (size_t k = 0; k + 1 < shape.size(); ++k) {
    const double piece = std::hypot(shape[k + 1].x - shape[k].x, shape[k + 1].y - shape[k].y);
    if (s <= walked + piece) {
      const double f = piece > 0.0 ? (s - walked) / piece : 0.0;
      return shape[k].y + f * (shape[k + 1].y - shape[k].y);
    }
    walked += piece;
  }
  return shape.empty() ? NAN : shape.back().y;
}

// y(s, t) at kMapColumns distances s in [0, length_mm] for the samples.
std::vector<std::vector<double>> MapValues(const std::vector<std::vector<BodyPoint>>& shapes,
                                           const std::vector<size_t>& samples, double length_mm) {
  std::vector<std::vector<double>> rows;
  for (size_t i : samples) {
    std::vector<double> row(kMapColumns);
    for (int c = 0; c < kMapColumns; ++c) {
      row[c] = LateralAlong(shapes[i], length_mm * c / (kMapColumns - 1));
    }
    rows.push_back(row);
  }
  return rows;
}

double LargestMagnitude(const std::vector<std::vector<double>>& rows) {
  double largest = 0.0;
  for (const std::vector<double>& row : rows) {
    for (double y : row) {
      if (std::isfinite(y)) largest = std::max(largest, std::abs(y));
    }
  }
  return largest;
}

// Rows "s t y", one block per sample, for a map drawn `with image`.
std::string MapData(const std::vector<std::vector<double>>& rows, const std::vector<double>& t_s,
                    const std::vector<size_t>& samples, double length_mm) {
  std::string text;
  for (size_t r = 0; r < samples.size(); ++r) {
    for (int c = 0; c < kMapColumns; ++c) {
      text += GnuplotValue(length_mm * c / (kMapColumns - 1)) + " " +
              GnuplotValue(t_s[samples[r]]) + " " + GnuplotValue(rows[r][c]) + "\n";
    }
    text += "\n";
  }
  return text;
}

}  // namespace

Figure SurfaceFigure(const CsvTable& table, const std::string& input, const FigureOptions& options,
                     const FigureScratch& scratch, FigureReport& report) {
  const nlohmann::json summary = SideJson(input, "summary.json");
  const BodyRecord body = ReadBodyRecord(table);
  RequireRows(table, 2);
  const std::vector<size_t> samples = Thinned(body.t_s.size(), options.max_lines);
  const bool with_ideal = !body.ideal.empty();
  // The map runs along the body (arc length s from the head), not along
  // x: bent, the body reaches less far along x than its length, which
  // would leave a blank staircase at the tail's end. Rigid links keep the
  // length of every sample; the map ends at the shortest.
  double length_mm = INFINITY;
  for (size_t i : samples) {
    length_mm = std::min(length_mm, ArcLength(body.realised[i]));
    if (with_ideal) length_mm = std::min(length_mm, ArcLength(body.ideal[i]));
  }
  if (!(length_mm > 0.0) || !std::isfinite(length_mm)) length_mm = 1.0;
  const std::vector<std::vector<double>> realised_rows =
      MapValues(body.realised, samples, length_mm);
  std::vector<std::vector<double>> ideal_rows, difference_rows;
  if (with_ideal) {
    ideal_rows = MapValues(body.ideal, samples, length_mm);
    difference_rows = realised_rows;
    for (size_t r = 0; r < difference_rows.size(); ++r) {
      for (int c = 0; c < kMapColumns; ++c) difference_rows[r][c] -= ideal_rows[r][c];
    }
  }
  double y_max = std::max(LargestMagnitude(realised_rows), LargestMagnitude(ideal_rows));
  if (!(y_max > 0.0)) y_max = 1.0;
  const std::string realised =
      scratch.Data("map_realised.dat", MapData(realised_rows, body.t_s, samples, length_mm));
  SetTitle(report, options, "Lateral deflection along the body over time", RunDescription(summary));
  // Each sample of the map is a pixel of `with image` centred on its
  // (s, t); the axes end at the body's ends and the record's.
  const std::string common =
      "unset grid\nunset key\nset tics out front\n"
      "set palette defined (-1 '#2166ac', -0.5 '#92c5de', 0 '#f7f7f7', 0.5 '#f4a582', 1 "
      "'#b2182b')\n"
      "set xrange [0:" +
      N(length_mm) +
      "]\n"
      "set yrange [" +
      N(body.t_s[samples.front()]) + ":" + N(body.t_s[samples.back()]) +
      "]\n"
      "set xlabel 's along the body [mm]'\n"
      "set ylabel " +
      Q(AxisLabel(columns::kTime)) + "\n";
  Figure figure;
  figure.height_in = 4.6;
  const double H = figure.height_in;
  const double top = 1.0 - 1.0 / H, bottom = 0.8 / H;
  std::string commands = "set multiplot title " + Heading(report) + "\n" + common;
  const auto colour_box = [&](double left, double width) {
    return "set colorbox user origin screen " + N(left) + ", screen " + N(bottom) +
           " size screen " + N(width) + ", screen " + N(top - bottom) + "\nset cbtics out\n";
  };
  const std::string deflection_bar = "set cbrange [" + N(-y_max) + ":" + N(y_max) +
                                     "]\nset cblabel 'lateral deflection y [mm]' offset 0.5,0\n";
  if (with_ideal) {
    double difference_max = LargestMagnitude(difference_rows);
    if (!(difference_max > 0.0)) difference_max = 1e-3;
    const std::string ideal =
        scratch.Data("map_ideal.dat", MapData(ideal_rows, body.t_s, samples, length_mm));
    const std::string difference = scratch.Data(
        "map_difference.dat", MapData(difference_rows, body.t_s, samples, length_mm));
    report.notes.push_back("realised - ideal: at most " + Format("%.4g", difference_max) +
                           " mm, the deflection at most " + Format("%.4g", y_max) + " mm");
    figure.width_in = 12.0;
    commands += PanelBox(0.085, 0.3, bottom, top) + deflection_bar +
                "unset colorbox\nset title 'ideal (references)'\n"
                "plot " +
                ideal + " using 1:2:3 with image\n" + PanelBox(0.335, 0.55, bottom, top) +
                colour_box(0.56, 0.012) +
                "set title 'realised (tips)'\nset ylabel ''\nset format y ''\n"
                "plot " +
                realised + " using 1:2:3 with image\n" + PanelBox(0.675, 0.885, bottom, top) +
                colour_box(0.895, 0.012) + "set cbrange [" + N(-difference_max) + ":" +
                N(difference_max) +
                "]\nset cblabel 'realised - ideal [mm]' offset 0.5,0\n"
                "set title 'realised - ideal (its own scale)'\n"
                "plot " +
                difference + " using 1:2:3 with image\n";
  } else {
    figure.width_in = 6.5;
    commands += PanelBox(0.13, 0.80, bottom, top) + colour_box(0.84, 0.03) + deflection_bar +
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

}  // namespace ipmc::figure_parts
