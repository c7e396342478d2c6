#include "renders/figures.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "renders/figure_parts.h"
#include "sim/io/csv.h"
#include "sim/io/files.h"
#include "sim/base/error.h"
#include "sim/base/numbers.h"

namespace ipmc {

using figure_parts::kMaxInstants;
using figure_parts::kMinMapRows;

const std::vector<std::string>& FigureKindNames() {
  static const std::vector<std::string> names = {
      "bode",       "step",           "tracking", "waveform", "surface",
      "trajectory", "identification", "sweep",    "compare", "regime"};
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

namespace {

constexpr int kMinImagePx = 200;
constexpr int kMaxImagePx = 10000;

}  // namespace

void FigureOptions::Validate(FigureKind kind) const {
  const auto fail = [](const std::string& option, const std::string& requirement,
                       const std::string& got) {
    throw FieldError("plot: " + option + " must be " + requirement + ", got " + got, option,
                     requirement);
  };
  const std::pair<const char*, int> sizes[] = {{"--width-px", size.width_px},
                                               {"--height-px", size.height_px}};
  for (const auto& [option, px] : sizes) {
    if (px != 0 && (px < kMinImagePx || px > kMaxImagePx)) {
      fail(option,
           "in [" + std::to_string(kMinImagePx) + ", " + std::to_string(kMaxImagePx) + "]",
           std::to_string(px));
    }
  }
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

namespace {

// Each kind-specific option and the kinds it applies to.
const std::vector<std::pair<std::string, std::vector<std::string>>>& OptionKinds() {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> table = {
      {"curves", {"bode"}},       {"instants", {"waveform"}},
      {"times-s", {"waveform"}},  {"period-s", {"waveform", "trajectory"}},
      {"max-lines", {"surface"}}, {"x", {"sweep"}},
      {"y", {"sweep"}},           {"group", {"sweep"}},
      {"log-x", {"sweep"}},       {"log-y", {"sweep"}},
      {"labels", {"compare"}}};
  return table;
}

}  // namespace

const std::vector<std::string>& FigureKindOptionNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> all;
    for (const auto& entry : OptionKinds()) all.push_back(entry.first);
    return all;
  }();
  return names;
}

void CheckFigureOptionsApply(FigureKind kind, const std::vector<std::string>& given) {
  const auto& option_kinds = OptionKinds();
  const std::string& kind_name = FigureKindNames()[static_cast<int>(kind)];
  for (const std::string& option : given) {
    const auto entry = std::find_if(option_kinds.begin(), option_kinds.end(),
                                    [&](const auto& e) { return option == e.first; });
    if (entry == option_kinds.end()) {
      std::string all;
      for (const auto& e : option_kinds) all += (all.empty() ? "" : ", ") + e.first;
      throw FieldError("plot: unknown option '" + option + "' (options: " + all + ")", option,
                       all);
    }
    bool applies = false;
    std::string names;
    for (const std::string& applies_to : entry->second) {
      applies = applies || kind_name == applies_to;
      names += (names.empty() ? "" : ", ") + applies_to;
    }
    if (!applies) {
      throw FieldError("plot: --" + option + " applies to plot " + names + " only, not " +
                           kind_name,
                       "--" + option, "plot " + names);
    }
  }
}

FigureReport DrawFigureOf(FigureKind kind, const std::vector<std::string>& inputs,
                          const FigureOptions& options, const std::string& out_path) {
  // An input, or a file of an input folder (a run's outputs), is never
  // the output.
  std::vector<std::string> inputs_and_theirs;
  for (const std::string& input : inputs) {
    inputs_and_theirs.push_back(input);
    inputs_and_theirs.push_back(
        (std::filesystem::path(input) / std::filesystem::path(out_path).filename()).string());
  }
  RefuseOverwritingInputs("plot", "--out", out_path, inputs_and_theirs);
  if (kind == FigureKind::kCompare) {
    options.Validate(kind);
    FigureFormatOf(out_path);
    if (inputs.size() < 2 || inputs.size() > static_cast<size_t>(kMaxComparedRuns)) {
      throw FieldError("plot compare: needs 2 to " + std::to_string(kMaxComparedRuns) +
                           " run directories, got " + std::to_string(inputs.size()),
                       "input", "2 to " + std::to_string(kMaxComparedRuns) + " run directories");
    }
    RequireWritableParent(out_path);
    FigureScratch scratch;
    FigureReport report;
    const Figure figure = figure_parts::CompareFigure(inputs, options, scratch, report);
    DrawFigure(figure, scratch, out_path, inputs.front(), options.size);
    return report;
  }
  if (inputs.size() != 1) {
    throw FieldError("plot " + FigureKindNames()[static_cast<int>(kind)] +
                         ": needs one input, got " + std::to_string(inputs.size()),
                     "input", "one file");
  }
  options.Validate(kind);
  RequireWritableParent(out_path);
  return DrawFigureOf(kind, inputs.front(), options, out_path);
}

FigureReport DrawFigureOf(FigureKind kind, const std::string& input, const FigureOptions& options,
                          const std::string& out_path) {
  if (kind == FigureKind::kCompare) {
    return DrawFigureOf(kind, std::vector<std::string>{input}, options, out_path);
  }
  options.Validate(kind);
  FigureFormatOf(out_path);  // an unknown format stops before anything is read
  FigureScratch scratch;
  FigureReport report;
  if (kind == FigureKind::kRegime) {
    const Figure figure = figure_parts::RegimeFigure(input, options, scratch, report);
    DrawFigure(figure, scratch, out_path, input, options.size);
    return report;
  }
  const CsvTable table = CsvTable::Read(input);
  using Builder = Figure (*)(const CsvTable&, const std::string&, const FigureOptions&,
                             const FigureScratch&, FigureReport&);
  using namespace figure_parts;
  const Builder builders[] = {BodeFigure,    StepFigure,       TrackingFigure,       WaveformFigure,
                              SurfaceFigure, TrajectoryFigure, IdentificationFigure, SweepFigure};
  const Figure figure = builders[static_cast<int>(kind)](table, input, options, scratch, report);
  DrawFigure(figure, scratch, out_path, input, options.size);
  return report;
}


FigureReport DrawConvergeFigure(const std::string& table_path, const std::string& out_path) {
  FigureOptions figure;
  figure.x_column = "resolution";
  figure.y_column = "swim_abs_error_percent";
  figure.group_column = "study";
  figure.log_x = figure.log_y = true;
  figure.title = "Swim error against each study's converged reference";
  return DrawFigureOf(FigureKind::kSweep, table_path, figure, out_path);
}

}  // namespace ipmc
