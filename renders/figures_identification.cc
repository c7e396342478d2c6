// The identification figure (Fig. 7): measured response, coherence, fits.
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

}  // namespace ipmc::figure_parts
