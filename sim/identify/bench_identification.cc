#include "sim/identify/bench_identification.h"

#include <random>

#include "sim/base/numbers.h"

namespace ipmc {

BenchIdentification IdentifyBenchRecord(const std::vector<double>& input_V,
                                        const std::vector<double>& output_mm,
                                        const BenchIdentificationOptions& options,
                                        unsigned long long stream) {
  std::vector<std::vector<double>> inputs(options.repeats, input_V);
  std::vector<std::vector<double>> outputs(options.repeats, output_mm);
  if (options.noise_mm > 0) {
    for (int r = 0; r < options.repeats; ++r) {
      std::mt19937_64 rng(options.seed + 1000003ULL * stream + r);
      std::normal_distribution<double> noise(0.0, options.noise_mm);
      for (double& y : outputs[r]) y += noise(rng);
    }
  }
  WelchOptions welch;
  welch.sample_rate_Hz = options.sample_rate_Hz;
  BenchIdentification result;
  result.estimate = EstimateFrequencyResponse(inputs, outputs, welch);
  result.levy = options.band;
  result.band_note = FitBandToData(result.levy, result.estimate);
  result.id = IdentifyLinkModels(result.estimate, result.levy);
  return result;
}

std::string FitBandToData(LevyOptions& levy, const FrequencyResponseEstimate& estimate) {
  if (levy.w_low_rad_s >= estimate.w_rad_s.front()) return "";
  const std::string note =
      FormatText("the band's low end %.4g rad/s is below the first Welch bin; the fit starts at "
                 "%.4g rad/s",
                 levy.w_low_rad_s, estimate.w_rad_s.front());
  levy.w_low_rad_s = estimate.w_rad_s.front();
  return note;
}

}  // namespace ipmc
