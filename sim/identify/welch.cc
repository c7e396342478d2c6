#include "sim/identify/welch.h"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <new>
#include <stdexcept>
#include <string>

#include "sim/base/numbers.h"

namespace ipmc {
namespace {

constexpr int kMaxSections = 1000;

// FFTW's planner is not thread-safe; fftw_execute on distinct plans is.
std::mutex& FftwPlannerMutex() {
  static std::mutex mutex;
  return mutex;
}

// A real-to-complex DFT of fixed length with its own FFTW buffers.
class RealFft {
 public:
  explicit RealFft(int n) : n_(n) {
    input_ = fftw_alloc_real(n);
    output_ = fftw_alloc_complex(n / 2 + 1);
    if (input_ == nullptr || output_ == nullptr) {
      Free();
      throw std::bad_alloc();
    }
    std::lock_guard<std::mutex> lock(FftwPlannerMutex());
    plan_ = fftw_plan_dft_r2c_1d(n, input_, output_, FFTW_ESTIMATE);
    if (plan_ == nullptr) {
      Free();
      throw std::runtime_error("welch: FFTW could not plan a transform of length " +
                               std::to_string(n));
    }
  }
  ~RealFft() { Free(); }
  RealFft(const RealFft&) = delete;
  RealFft& operator=(const RealFft&) = delete;

  double* input() { return input_; }
  std::complex<double> Output(int m) const { return {output_[m][0], output_[m][1]}; }
  void Execute() { fftw_execute(plan_); }
  int size() const { return n_; }

 private:
  void Free() {
    if (plan_ != nullptr) {
      std::lock_guard<std::mutex> lock(FftwPlannerMutex());
      fftw_destroy_plan(plan_);
      plan_ = nullptr;
    }
    if (input_ != nullptr) fftw_free(input_);
    if (output_ != nullptr) fftw_free(output_);
    input_ = nullptr;
    output_ = nullptr;
  }

  int n_;
  double* input_ = nullptr;
  fftw_complex* output_ = nullptr;
  fftw_plan plan_ = nullptr;
};

[[noreturn]] void Throw(const std::string& message) {
  throw std::invalid_argument("welch: " + message);
}

void CheckFinite(const std::vector<double>& values, const std::string& field) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      Throw(field + " is not finite at sample " + std::to_string(i) + " (got " +
            FormatDouble(values[i]) + ")");
    }
  }
}

// Copies section [start, start + L) of `data` into fft.input() with its
// mean removed and the window applied.
void LoadSection(const std::vector<double>& data, long start, const std::vector<double>& window,
                 RealFft& fft) {
  const int length = fft.size();
  double mean = 0.0;
  for (int n = 0; n < length; ++n) mean += data[start + n];
  mean /= length;
  double* in = fft.input();
  for (int n = 0; n < length; ++n) in[n] = (data[start + n] - mean) * window[n];
}

double LargestMagnitude(const std::vector<std::vector<double>>& records) {
  double largest = 0.0;
  for (const std::vector<double>& record : records) {
    for (double value : record) largest = std::max(largest, std::abs(value));
  }
  return largest;
}

// The sums of squares overflow for records of about 1e150 and beyond:
// refused, not passed on as inf and nan.
void RequireFiniteSpectra(const std::vector<double>& sxx, const std::vector<double>& syy,
                          const std::vector<std::complex<double>>& sxy,
                          const std::vector<std::vector<double>>& inputs,
                          const std::vector<std::vector<double>>& outputs) {
  for (std::size_t m = 0; m < sxx.size(); ++m) {
    if (std::isfinite(sxx[m]) && std::isfinite(syy[m]) && std::isfinite(sxy[m].real()) &&
        std::isfinite(sxy[m].imag())) {
      continue;
    }
    Throw("the spectra are not finite (largest |input| " +
          FormatDouble(LargestMagnitude(inputs), 6) + ", |output| " +
          FormatDouble(LargestMagnitude(outputs), 6) +
          "): records this large overflow their squares");
  }
}

}  // namespace

void WelchOptions::Validate() const {
  if (!std::isfinite(sample_rate_Hz) || !(sample_rate_Hz > 0)) {
    Throw("sample_rate_Hz must be finite and > 0 (got " + FormatDouble(sample_rate_Hz) + ")");
  }
  if (sections < 1 || sections > kMaxSections) {
    Throw("sections must be in [1, " + std::to_string(kMaxSections) + "] (got " +
          std::to_string(sections) + ")");
  }
  if (!std::isfinite(overlap) || overlap < 0 || !(overlap < 1)) {
    Throw("overlap must be in [0, 1) (got " + FormatDouble(overlap) + ")");
  }
  if (minimum_section_samples < 4) {
    Throw("minimum_section_samples must be >= 4 (got " +
          std::to_string(minimum_section_samples) + ")");
  }
}

int WelchOptions::SectionSamples(long samples) const {
  const double divisor = 1.0 + (sections - 1) * (1.0 - overlap);
  long length = static_cast<long>(std::floor(samples / divisor));
  // Lower L until K sections fit after the rounding of the overlap.
  while (length > 0) {
    const long step = length - static_cast<long>(std::floor(overlap * length));
    if (step >= 1 && (sections - 1) * step + length <= samples) break;
    --length;
  }
  return static_cast<int>(length);
}

long WelchOptions::MinimumSamples() const {
  long samples = static_cast<long>(
      std::ceil(minimum_section_samples * (1.0 + (sections - 1) * (1.0 - overlap))));
  samples = std::max(samples - 2, 1L);
  while (SectionSamples(samples) < minimum_section_samples) ++samples;
  return samples;
}

FrequencyResponseEstimate EstimateFrequencyResponse(const std::vector<double>& input,
                                                    const std::vector<double>& output,
                                                    const WelchOptions& options) {
  return EstimateFrequencyResponse(std::vector<std::vector<double>>{input},
                                   std::vector<std::vector<double>>{output}, options);
}

FrequencyResponseEstimate EstimateFrequencyResponse(
    const std::vector<std::vector<double>>& inputs,
    const std::vector<std::vector<double>>& outputs, const WelchOptions& options) {
  options.Validate();
  if (inputs.empty()) Throw("no records (inputs is empty)");
  if (inputs.size() != outputs.size()) {
    Throw("outputs has " + std::to_string(outputs.size()) + " records, inputs " +
          std::to_string(inputs.size()));
  }
  const long samples = static_cast<long>(inputs[0].size());
  const bool single = inputs.size() == 1;
  for (std::size_t r = 0; r < inputs.size(); ++r) {
    const std::string suffix = single ? "" : "[" + std::to_string(r) + "]";
    if (static_cast<long>(inputs[r].size()) != samples) {
      Throw("input" + suffix + " has " + std::to_string(inputs[r].size()) +
            " samples, input[0] " + std::to_string(samples) + " (records must have equal lengths)");
    }
    if (outputs[r].size() != inputs[r].size()) {
      Throw("output" + suffix + " has " + std::to_string(outputs[r].size()) +
            " samples, input" + suffix + " " + std::to_string(inputs[r].size()));
    }
    CheckFinite(inputs[r], "input" + suffix);
    CheckFinite(outputs[r], "output" + suffix);
  }
  const long minimum = options.MinimumSamples();
  if (samples < minimum) {
    Throw("input has " + std::to_string(samples) + " samples, fewer than the minimum " +
          std::to_string(minimum) + " for " + std::to_string(options.sections) +
          " sections of >= " + std::to_string(options.minimum_section_samples) +
          " samples with " + FormatDouble(100 * options.overlap) + " % overlap");
  }

  const int length = options.SectionSamples(samples);
  const int step = length - static_cast<int>(std::floor(options.overlap * length));
  const int bins = length / 2;  // m = 1..bins
  std::vector<double> window(length);
  double window_power = 0.0;
  for (int n = 0; n < length; ++n) {
    window[n] = 0.54 - 0.46 * std::cos(kTwoPi * n / (length - 1));
    window_power += window[n] * window[n];
  }

  RealFft fft_x(length);
  RealFft fft_y(length);
  const std::size_t records = inputs.size();
  std::vector<double> sxx(bins + 1, 0.0), syy(bins + 1, 0.0);
  std::vector<std::complex<double>> sxy(bins + 1, 0.0);
  std::vector<std::vector<double>> record_magnitude(records > 1 ? records : 0);
  for (std::size_t r = 0; r < records; ++r) {
    std::vector<double> rxx(bins + 1, 0.0);
    std::vector<std::complex<double>> rxy(bins + 1, 0.0);
    for (int k = 0; k < options.sections; ++k) {
      const long start = static_cast<long>(k) * step;
      LoadSection(inputs[r], start, window, fft_x);
      LoadSection(outputs[r], start, window, fft_y);
      fft_x.Execute();
      fft_y.Execute();
      for (int m = 1; m <= bins; ++m) {
        const std::complex<double> x = fft_x.Output(m);
        const std::complex<double> y = fft_y.Output(m);
        rxx[m] += std::norm(x);
        rxy[m] += std::conj(x) * y;
        syy[m] += std::norm(y);
      }
    }
    for (int m = 1; m <= bins; ++m) {
      sxx[m] += rxx[m];
      sxy[m] += rxy[m];
    }
    if (records > 1) {
      record_magnitude[r].resize(bins + 1);
      for (int m = 1; m <= bins; ++m) {
        record_magnitude[r][m] = rxx[m] > 0 ? std::abs(rxy[m] / rxx[m]) : 0.0;
      }
    }
  }

  RequireFiniteSpectra(sxx, syy, sxy, inputs, outputs);

  FrequencyResponseEstimate estimate;
  estimate.section_samples = length;
  estimate.section_step = step;
  estimate.sections_per_record = options.sections;
  estimate.records = static_cast<int>(records);
  estimate.sample_rate_Hz = options.sample_rate_Hz;
  const double fs = options.sample_rate_Hz;
  const double psd_scale =
      1.0 / (static_cast<double>(records) * options.sections * fs * window_power);
  for (int m = 1; m <= bins; ++m) {
    const double f = m * fs / length;
    const double one_sided = (2 * m == length) ? 1.0 : 2.0;
    estimate.frequency_Hz.push_back(f);
    estimate.w_rad_s.push_back(kTwoPi * f);
    estimate.response.push_back(sxx[m] > 0 ? sxy[m] / sxx[m] : std::complex<double>(0.0));
    const double denominator = sxx[m] * syy[m];
    estimate.coherence.push_back(denominator > 0 ? std::norm(sxy[m]) / denominator : 0.0);
    estimate.input_psd.push_back(one_sided * psd_scale * sxx[m]);
    estimate.output_psd.push_back(one_sided * psd_scale * syy[m]);
    if (records > 1) {
      double mean = 0.0;
      for (std::size_t r = 0; r < records; ++r) mean += record_magnitude[r][m];
      mean /= records;
      double variance = 0.0;
      for (std::size_t r = 0; r < records; ++r) {
        variance += (record_magnitude[r][m] - mean) * (record_magnitude[r][m] - mean);
      }
      estimate.magnitude_std.push_back(std::sqrt(variance / (records - 1)));
    }
  }
  return estimate;
}

}  // namespace ipmc
