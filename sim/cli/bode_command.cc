#include "sim/cli/bode_command.h"

#include <complex>
#include <cstdio>

#include "sim/linear/frequency_response.h"

namespace ipmc {
namespace {

using Complex = std::complex<double>;

void PrintBode(const BodeSpec& spec, const BodeAnalysis& analysis) {
  const StabilityMargins& margins = analysis.margins;
  std::printf("link %d: open loop L = C x P, controller %s, plant %s (exact fractional response)\n",
              spec.link, spec.controller.c_str(), spec.plant.c_str());
  std::printf("  %s\n  %s\n", analysis.controller_description.c_str(),
              analysis.plant_description.c_str());
  std::printf("margins searched over [%g, %g] rad/s:\n", analysis.search.grid.w_low_rad_s,
              analysis.search.grid.w_high_rad_s);
  if (margins.gain_crossover_rad_s) {
    std::printf("gain crossover: %.3f rad/s\n", *margins.gain_crossover_rad_s);
    std::printf("phase margin: %.2f deg\n", *margins.phase_margin_deg);
    if (margins.gain_crossovers_rad_s.size() > 1) {
      std::printf("  (%zu gain crossovers; the lowest is reported)\n",
                  margins.gain_crossovers_rad_s.size());
    }
  } else {
    std::printf("gain crossover: none (|L| does not cross 1)\n");
  }
  if (margins.gain_margin_dB) {
    std::printf("gain margin: %.2f dB at %.3f rad/s\n", *margins.gain_margin_dB,
                *margins.phase_crossover_rad_s);
  } else {
    std::printf("gain margin: no finite gain margin (the phase does not reach -180 deg)\n");
  }
  const Complex c5 = analysis.controller_at_design;
  const Complex p5 = analysis.plant_at_design;
  std::printf("at %g rad/s: controller %.2f dB, %.2f deg; plant %.2f dB, %.2f deg; "
              "open loop %.2f dB, %.2f deg\n",
              analysis.design_frequency_rad_s, MagnitudeDb(c5), PhaseDeg(c5), MagnitudeDb(p5),
              PhaseDeg(p5), MagnitudeDb(c5 * p5), PhaseDeg(c5 * p5));
}

}  // namespace

void AddBodeCommand(CLI::App& app, BodeArgs& args) { AddTableCommand(app, BodeOptions(), args); }

int RunBodeCommandLine(const BodeArgs& args) {
  if (!args.Chosen()) return -1;
  const std::vector<BodeLink> links = TranslatingFieldErrors(
      BodeOptions(), [&] { return RunBodeCommand(args.spec, args.Given()); });
  for (const BodeLink& link : links) {
    if (&link != &links.front()) std::printf("\n");
    PrintBode(link.spec, link.analysis);
  }
  return 0;
}

}  // namespace ipmc
