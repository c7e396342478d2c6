// What the figure builders (renders/figures_*.cc) share: colours, gnuplot
// text, the JSON files a command writes beside its CSV, titles; and the
// builders themselves, one per figure kind, which DrawFigureOf
// (renders/figures.h) picks by kind.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "renders/figure_labels.h"
#include "renders/figures.h"
#include "renders/gnuplot_figure.h"
#include "sim/io/csv.h"

namespace ipmc::figure_parts {

// At most this many instants in the waveform figure; at least this many
// time rows in the x-t map.
constexpr int kMaxInstants = 12;
constexpr int kMinMapRows = 2;

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

std::string Q(const std::string& text);
std::string N(double value);
std::string Rgb(const char* colour);
// printf of one number.
std::string Format(const char* format, double value);
// "speed [mm/s]" -> "speed": a label as words in a title.
std::string WithoutUnit(const std::string& label);
// A tic step of 1, 2 or 5 x 10^k that cuts `span` into about `count`.
double NiceStep(double span, int count);
// Margins that pin a panel to a box of the canvas (fractions of it).
std::string PanelBox(double left, double right, double bottom, double top);
// Panels stacked in inches from the top of a canvas `height_in` tall:
// the box of a panel `top_in` below the top, `tall_in` tall.
std::string StackedPanel(double height_in, double top_in, double tall_in, double left = 0.12,
                         double right = 0.97);
// Throws InputError naming the table unless it has `rows` data rows.
void RequireRows(const CsvTable& table, std::size_t rows);
// The intervals [start, end] [s] over which a recorded voltage sits at the
// clamp (|v| >= V_max, to 1e-9): each run of consecutive samples at it,
// from half-way to the sample before its first to half-way to the sample
// after its last (the record's own ends at its ends). None without a
// clamp. The tracking figure shades them, each apart, so that the shade
// covers the clamped samples and nothing between them.
struct ClampInterval {
  double start_s = 0, end_s = 0;
  std::size_t samples = 0;
};
std::vector<ClampInterval> ClampIntervals(const std::vector<double>& time_s,
                                          const std::vector<double>& voltage, bool clamp,
                                          double v_max);
// A JSON file the same command wrote beside `input`; null if there is none
// or it does not parse.
nlohmann::json SideJson(const std::string& input, const std::string& name);
// A string or number member of a JSON object; "" or `otherwise` if absent.
std::string JsonText(const nlohmann::json& json, const char* key);
double JsonNumber(const nlohmann::json& json, const char* key, double otherwise);
// What a run's summary.json says it was, for titles: "PID, clamp +-6 V,
// distributed actuation (paper)", or the gait; "" without a summary.
std::string RunDescription(const nlohmann::json& summary);
// The title: the caller's, or what is shown with its context on a second
// line.
void SetTitle(FigureReport& report, const FigureOptions& options, const std::string& what,
              const std::string& context);
std::string Heading(const FigureReport& report);

// The steady cycles of a run recorded at times t [s] with wave period
// `period_s`: every cycle after the first (whose start ramp and transient
// are not steady), from t = period_s on, if the record holds at least two
// cycles; else the whole record. `what` says which ("cycles 2-3", "the
// run").
struct SteadyCycles {
  double from_s = 0.0;
  std::string what;
};
SteadyCycles SteadyCyclesOf(const std::vector<double>& t_s, double period_s);
// The root mean square of measured - reference over the samples from
// from_s on; NaN without samples.
double RmsError(const std::vector<double>& t_s, const std::vector<double>& reference,
                const std::vector<double>& measured, double from_s);

// The builders: the figure of one kind from its CSV table (read from
// `input`); throw InputError for input without the columns or rows needed.
#define IPMC_FIGURE_BUILDER(name)                                                         \
  Figure name(const CsvTable& table, const std::string& input, const FigureOptions& options, \
              const FigureScratch& scratch, FigureReport& report)
IPMC_FIGURE_BUILDER(BodeFigure);            // renders/figures_frequency.cc
IPMC_FIGURE_BUILDER(StepFigure);            // renders/figures_frequency.cc
IPMC_FIGURE_BUILDER(TrackingFigure);        // renders/figures_run.cc
IPMC_FIGURE_BUILDER(WaveformFigure);        // renders/figures_run.cc
IPMC_FIGURE_BUILDER(SurfaceFigure);         // renders/figures_run.cc
IPMC_FIGURE_BUILDER(TrajectoryFigure);      // renders/figures_run.cc
IPMC_FIGURE_BUILDER(IdentificationFigure);  // renders/figures_identification.cc
IPMC_FIGURE_BUILDER(SweepFigure);           // renders/figures_sweep.cc
#undef IPMC_FIGURE_BUILDER
// A run's summary.json: its Reynolds number against frequency and
// viscosity (renders/figures_regime.cc).
Figure RegimeFigure(const std::string& summary_path, const FigureOptions& options,
                    const FigureScratch& scratch, FigureReport& report);
// Several run directories (renders/figures_compare.cc).
Figure CompareFigure(const std::vector<std::string>& run_dirs, const FigureOptions& options,
                     const FigureScratch& scratch, FigureReport& report);

}  // namespace ipmc::figure_parts
