#include "sim/identify/report_text.h"

#include <cmath>

#include "sim/base/numbers.h"

namespace ipmc {

std::string StabilityText(const LinkModelFit& fit) { return fit.stable ? "stable" : "UNSTABLE"; }

std::string DescribeG1(const LinkModelFit& fit) {
  const IpmcLinkParams& p = fit.params;
  std::string text = FormatText("G1 = a0 / (b2 s^2 + b1 s + 1): a0 = %.5g mm/V, b1 = %.5g s, "
                            "b2 = %.5g s^2 (%s",
                            p.a0_mm_per_V, p.b1, p.b2_s2, StabilityText(fit).c_str());
  if (p.b2_s2 > 0 && p.b1 > 0) {
    text += FormatText("; zeta = %.4f, w_n = %.4g rad/s", p.b1 / (2 * std::sqrt(p.b2_s2)),
                   1 / std::sqrt(p.b2_s2));
  }
  return text + ")";
}

std::string DescribeG2(const LinkModelFit& fit, const LinkIdentification& id) {
  const IpmcLinkParams& p = fit.params;
  return FormatText("G2 = a0 / (b1 s^alpha + 1): alpha = %.2f, a0 = %.5g mm/V, b1 = %.5g s^alpha "
                "(%s; %d of %d orders stable)",
                p.alpha, p.a0_mm_per_V, p.b1, StabilityText(fit).c_str(), id.g2_orders_stable,
                id.g2_orders_tried);
}

std::string WelchDescription(const FrequencyResponseEstimate& e) {
  const double resolution_Hz = e.sample_rate_Hz / e.section_samples;
  return FormatText("Welch: %d record%s x %d sections of %d samples (%.4g s), %d-sample step "
                "(50 %% overlap), Hamming window; resolution %.4g Hz (%.4g rad/s)",
                e.records, e.records == 1 ? "" : "s", e.sections_per_record, e.section_samples,
                e.section_samples / e.sample_rate_Hz, e.section_step, resolution_Hz,
                kTwoPi * resolution_Hz);
}

double MeanCoherenceInBand(const FrequencyResponseEstimate& e, const FitIndices& indices) {
  double sum = 0;
  int count = 0;
  for (std::size_t i = 0; i < e.w_rad_s.size(); ++i) {
    if (e.w_rad_s[i] >= indices.w_first_rad_s && e.w_rad_s[i] <= indices.w_last_rad_s) {
      sum += e.coherence[i];
      ++count;
    }
  }
  return count > 0 ? sum / count : 0.0;
}

std::string MarginsText(const StabilityMargins& m) {
  std::string text = m.gain_crossover_rad_s
                         ? FormatText("crossover %.4f rad/s, phase margin %.2f deg",
                                      *m.gain_crossover_rad_s, *m.phase_margin_deg)
                         : std::string("no gain crossover");
  text += m.gain_margin_dB ? FormatText(", gain margin %.2f dB at %.4g rad/s", *m.gain_margin_dB,
                                        *m.phase_crossover_rad_s)
                           : std::string(", no finite gain margin");
  return text;
}

std::string PidText(const PidGains& g) {
  return FormatText("C(s) = %.4g + %.4g/s + %.4g s", g.kp, g.ki, g.kd);
}

}  // namespace ipmc
