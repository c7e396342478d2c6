#include "renders/figures.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "renders/figure_parts.h"
#include "sim/io/csv.h"
#include "plugin/base/error.h"
#include "plugin/base/numbers.h"

namespace ipmc {

using figure_parts::kMaxInstants;
using figure_parts::kMinMapRows;

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
  using namespace figure_parts;
  const Builder builders[] = {BodeFigure,    StepFigure,       TrackingFigure,       WaveformFigure,
                              SurfaceFigure, TrajectoryFigure, IdentificationFigure, SweepFigure};
  const Figure figure = builders[static_cast<int>(kind)](table, input, options, scratch, report);
  DrawFigure(figure, scratch, out_path, input, options.size);
  return report;
}


}  // namespace ipmc
