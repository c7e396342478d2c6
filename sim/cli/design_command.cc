#include "sim/cli/design_command.h"

#include <cstdio>

#include "controllers/fractional_integrator.h"
#include "sim/base/numbers.h"
#include "sim/identify/report_text.h"

namespace ipmc {
namespace {


// The derivative filter against the usual N = Td / Tf = Kd / (Kp Tf) of 2
// to 20 (Astrom & Murray, Feedback Systems, sec. 10.5), and against the
// sensor's noise where it was designed from it.
void PrintDerivativeFilter(const DesignCommand& command, const LinkDesign& result) {
  const double filter_s = result.tuning.derivative_filter_s;
  const PidGains& g = result.tuned.gains;
  if (command.sensor_noise_mm > 0) {
    std::printf("  derivative filter from the sensor's %g mm RMS noise: Tf = %.4g s, derivative "
                "noise %.4g V RMS (bound %g V)\n",
                command.sensor_noise_mm, filter_s, result.derivative_noise_V,
                command.derivative_noise_V);
  }
  if (filter_s > 0 && g.kp > 0) {
    const double n = g.kd / (g.kp * filter_s);
    std::printf("  N = Td / Tf = %.3g%s\n", n,
                n < 2 || n > 20 ? " (outside the usual 2 to 20)" : " (within the usual 2 to 20)");
  }
}

void PrintDesign(const DesignSpec& args, const DesignCommand& command,
                 const std::string& plant_file, const LinkDesign& result) {
  const IpmcLinkParams& p = result.params;
  if (!plant_file.empty()) {
    const bool g2 = p.kind == IpmcModelKind::kG2;
    std::printf("plant: link %d, P = s^-0.5 %s, a0 = %.6g mm/V, b1 = %.6g, %s = %.6g (%s)\n",
                args.link, g2 ? "G2" : "G1", p.a0_mm_per_V, p.b1, g2 ? "alpha" : "b2",
                g2 ? p.alpha : p.b2_s2, plant_file.c_str());
  } else {
    std::printf("plant: link %d, P = s^-0.5 %s (Table 2%s)\n", args.link,
                args.plant == "g2" ? "G2" : "G1",
                args.link == 3 && args.plant == "g1" ? ", eq. 7" : "");
  }
  const FractionalIntegratorDesign& d = result.fractional.design;
  std::printf("fractional integrator for crossover %g rad/s, phase margin %g deg:\n",
              args.crossover_rad_s, args.phase_margin_deg);
  std::printf("  |P(j w_c)| = %.6g mm/V, arg P(j w_c) = %.4f deg\n", d.plant_magnitude,
              d.plant_phase_deg);
  std::printf("  C_I(s) = %.4f / s^%.4f  (lambda = (arg P + 180 - PM) / 90, K = w_c^lambda / "
              "|P|; paper eq. 14: %.2f / s^%.2f)\n",
              d.gain, d.order, kPaperFractional.gain, kPaperFractional.order);
  std::printf("  open loop (exact): %s\n", MarginsText(result.fractional.margins).c_str());

  const PidTuningResult& tuned = result.tuned;
  std::printf("PID tuned by Nelder-Mead against 1/((s/%g)^%g + 1), J of eq. 11 over %g s, loop "
              "sampled at %g Hz (linear, no clamp%s):\n",
              args.crossover_rad_s, args.reference_order, args.horizon_s, args.sample_rate_Hz,
              args.derivative_filter_s > 0
                  ? (", derivative filter Tf = " + FormatDouble(args.derivative_filter_s, 4) + " s")
                        .c_str()
                  : "");
  std::printf("  %-34s %-34s %10s %10s %6s\n", "start", "result", "J_start", "J", "evals");
  for (const PidTuningRun& run : tuned.runs) {
    std::printf("  %-34s %-34s %10.6f %10.6f %6d%s\n", PidText(run.start).c_str(),
                PidText(run.gains).c_str(), run.start_cost, run.cost, run.evaluations,
                run.converged ? "" : " (not converged)");
  }
  std::printf("  paper (eq. 12): %s, J = %.6f\n", PidText(kPaperPid).c_str(), result.paper_cost);
  std::printf("  tuned:          %s, J = %.6f (%.1f %% of the paper's)\n",
              PidText(tuned.gains).c_str(), tuned.cost, 100 * tuned.cost / result.paper_cost);
  std::printf("  tuned open loop (exact plant, continuous PID%s): %s\n",
              args.derivative_filter_s > 0 ? " with its filter" : "",
              MarginsText(result.pid_margins).c_str());
  PrintDerivativeFilter(command, result);
  std::printf("  tuning time %.2f s\n", result.tuning_s);
}

}  // namespace

void AddDesignCommand(CLI::App& app, DesignArgs& args) {
  AddTableCommand(app, DesignOptions(), args);
}

int RunDesignCommandLine(const DesignArgs& args) {
  if (!args.Chosen()) return -1;
  const std::vector<LinkDesign> designs = TranslatingFieldErrors(
      DesignOptions(), [&] { return RunDesignCommand(args.spec, args.Given()); });
  const std::string& plants =
      args.spec.scenario.empty() ? args.spec.plant_file : args.spec.scenario;
  for (std::size_t i = 0; i < designs.size(); ++i) {
    if (i > 0) std::printf("\n");
    DesignSpec spec = args.spec;
    spec.link = designs[i].link;
    spec.sample_rate_Hz = 1.0 / designs[i].tuning.sample_period_s;
    spec.derivative_filter_s = designs[i].tuning.derivative_filter_s;
    PrintDesign(spec, args.spec, plants, designs[i]);
  }
  if (!args.spec.out.empty()) std::printf("\nwrote %s\n", args.spec.out.c_str());
  return 0;
}

}  // namespace ipmc
