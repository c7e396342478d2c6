// The flow regime of a run's strip: its largest Reynolds number (tip,
// swim, oscillatory, sim/core/swim_meter.h) carried to other frequencies
// and viscosities. At a given wave shape every one of them goes as
// rho f / mu (the tip's and the body's speeds as f, the oscillatory
// rho omega w^2 / (4 mu) by definition), so Re = const is the line
// mu = mu_0 Re_0 f / (f_0 Re) on logarithmic axes.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include "renders/figure_parts.h"
#include "sim/base/error.h"

namespace ipmc::figure_parts {
namespace {

// Test liquids at 20 degC [Pa s], drawn across the map.
struct Liquid {
  const char* name;
  double viscosity_Pa_s;
};
// Water: CRC Handbook of Chemistry and Physics (1.002 mPa s); glycerol:
// Segur & Oberstar, Ind. Eng. Chem. 43, 2117 (1951) (1.412 Pa s);
// silicone oils (polydimethylsiloxane): their nominal grades, 0.1, 1 and
// 10 Pa s (100, 1000, 10000 cSt at 0.97 g/cm^3).
constexpr Liquid kLiquids[] = {{"water", 1.002e-3},
                               {"silicone oil 100 cSt", 0.097},
                               {"silicone oil 1000 cSt", 0.97},
                               {"glycerol", 1.412},
                               {"silicone oil 10000 cSt", 9.7}};

double Required(const nlohmann::json& summary, const char* key, const std::string& input) {
  const double value = JsonNumber(summary, key, NAN);
  if (!std::isfinite(value) || value <= 0.0) {
    throw InputError(InputProblem::kMissing, {input, 0}, key,
                     std::string("plot regime: ") + key +
                         " must be a positive number in the run's summary.json",
                     "a run's summary.json");
  }
  return value;
}

}  // namespace

Figure RegimeFigure(const std::string& input, const FigureOptions& options,
                    const FigureScratch& scratch, FigureReport& report) {
  std::ifstream file(input);
  const nlohmann::json summary = nlohmann::json::parse(file, nullptr, false);
  if (!summary.is_object()) {
    throw InputError(InputProblem::kBadValue, {input, 0}, "summary.json",
                     "plot regime: the input must be a run's summary.json", "a run's summary.json");
  }
  const double f0_Hz = Required(summary, "frequency_Hz", input);
  const double mu0_Pa_s = Required(summary, "viscosity_Pa_s", input);
  const double re0 = std::max({JsonNumber(summary, "reynolds_tip", 0.0),
                               JsonNumber(summary, "reynolds_swim", 0.0),
                               JsonNumber(summary, "reynolds_oscillatory", 0.0)});
  if (!(re0 > 0.0)) Required(summary, "reynolds_tip", input);
  // mu at Re = 1 per Hz.
  const double slope = mu0_Pa_s * re0 / f0_Hz;
  const double f_min = std::pow(10.0, std::floor(std::log10(f0_Hz)) - 2.0);
  const double f_max = std::pow(10.0, std::floor(std::log10(f0_Hz)) + 2.0);
  const double mu_min = 1e-4, mu_max = 1e2;
  report.notes.push_back("Re = 0.1 at " + Format("%.3g", f0_Hz) + " Hz: viscosity " +
                         Format("%.3g", slope * f0_Hz / 0.1) + " Pa s; in this liquid (" +
                         Format("%.3g", mu0_Pa_s) + " Pa s): " +
                         Format("%.3g", mu0_Pa_s * 0.1 / slope) + " Hz");
  std::string liquids;
  for (const Liquid& liquid : kLiquids) {
    liquids += "set arrow from " + N(f_min) + "," + N(liquid.viscosity_Pa_s) + " to " + N(f_max) +
               "," + N(liquid.viscosity_Pa_s) + " nohead front dt 2 lw 1 lc " + Rgb(kGrey) + "\n" +
               "set label " + Q(liquid.name) + " at " + N(f_min * 1.3) + "," +
               N(liquid.viscosity_Pa_s * 1.25) + " left front font ',10' tc rgb 'black'\n";
  }
  const std::string point = scratch.Data("run.dat", N(f0_Hz) + " " + N(mu0_Pa_s) + "\n");
  SetTitle(report, options, "Flow regime: the largest Reynolds number against frequency and viscosity",
           "this strip and wave shape; Re " + Format("%.3g", re0) + " at " + Format("%.3g", f0_Hz) +
               " Hz, " + Format("%.3g", mu0_Pa_s) + " Pa s");
  const auto mu_at = [&](double re) { return "(" + N(slope / re) + " * $1)"; };
  Figure figure;
  figure.width_in = 9.5;
  figure.height_in = 5.5;
  figure.commands =
      "set title " + Heading(report) + "\n" +
      "set logscale xy\nset format x '%g'\nset format y '%g'\n"
      "set xrange [" + N(f_min) + ":" + N(f_max) + "]\nset yrange [" + N(mu_min) + ":" +
      N(mu_max) + "]\n"
      "set xlabel 'wave frequency [Hz]'\nset ylabel 'viscosity [Pa s]'\n"
      "set samples 200\nset key outside right top box\n" + liquids +
      "plot '+' using 1:" + mu_at(0.1) + ":(" + N(mu_max) +
      ") with filledcurves lc rgb '#cfe3c8' title 'Stokes flow, Re < 0.1', "
      "'+' using 1:" + mu_at(1.0) + ":" + mu_at(0.1) +
      " with filledcurves lc rgb '#f3ecc2' title '0.1 < Re < 1', "
      "'+' using 1:" + mu_at(1.0) + " with lines lw 1.5 lc " + Rgb(kRed) +
      " title 'Re = 1', '+' using 1:" + mu_at(10.0) + " with lines lw 1 dt 3 lc " + Rgb(kRed) +
      " title 'Re = 10', " + point + " using 1:2 with points pt 7 ps 2 lc " + Rgb(kBlue) +
      " title 'this run'\n";
  return figure;
}

}  // namespace ipmc::figure_parts
