// Frequency response from sampled input/output data by Welch's method, as
// the paper measures it (section 4.1): each record is split into K = 8
// sections with 50 % overlap, every section has its mean removed and is
// multiplied by a Hamming window, and the modified periodograms of the
// sections are averaged:
//
//   S_xx(f) = sum_r,k |X_rk(f)|^2,  S_yy(f) = sum_r,k |Y_rk(f)|^2,
//   S_xy(f) = sum_r,k conj(X_rk(f)) Y_rk(f),
//   H1(f)   = S_xy(f) / S_xx(f),
//   gamma^2(f) = |S_xy(f)|^2 / (S_xx(f) S_yy(f))   (coherence, in [0, 1]),
//
// with X_rk, Y_rk the discrete Fourier transforms (FFTW, real to complex) of
// section k of record r. Several records of the same experiment (the
// paper repeats each one 10 times) are averaged by pooling their
// sections' spectra, which is H1 over all R K sections; the spread of the
// per-record responses |H1_r| is reported as a standard deviation.
//
// Sections (as MATLAB's pwelch/tfestimate with their defaults): with N
// samples per record, K sections and overlap fraction v, the section
// length is L = floor(N / (1 + (K - 1)(1 - v))), consecutive sections
// overlap by floor(v L) samples (L is lowered by a sample or two where
// that rounding would push the last section past the end), and samples
// after the last section are unused. The Hamming window is the symmetric one,
// w[n] = 0.54 - 0.46 cos(2 pi n / (L - 1)). The DFT length is L, so the
// bins are f_m = m fs / L, m = 1..floor(L/2) (DC is left out: the mean is
// removed). Units: H1 in output units per input unit (mm/V for the bench);
// the one-sided power spectral densities
//   PSD_x(f) = 2 S_xx(f) / (R K fs sum_n w[n]^2)   (not doubled at Nyquist)
// are in input (output) units squared per Hz.
//
// Bad input throws std::invalid_argument with one line naming the field:
// a non-finite sample, records of different lengths, input and output of
// different lengths, too few samples for the sections (the message gives
// the minimum), a sample rate that is not finite and > 0, records so large
// (about 1e150 and beyond) that the spectra overflow.
#pragma once

#include <complex>
#include <vector>

namespace ipmc {

struct WelchOptions {
  double sample_rate_Hz = 1000.0;  // fs, finite and > 0
  int sections = 8;                // K, in [1, 1000]
  double overlap = 0.5;            // v, in [0, 1)
  // Sections must hold at least this many samples (then
  // MinimumWelchSamples() is the shortest record accepted).
  int minimum_section_samples = 16;  // >= 4

  // Throws std::invalid_argument naming the field and its allowed range.
  void Validate() const;
  // The section length L for records of `samples` samples (may be < the
  // minimum; Validate the data to reject that).
  int SectionSamples(long samples) const;
  // The fewest samples per record that give sections of at least
  // minimum_section_samples (72 for the defaults).
  long MinimumSamples() const;
};

struct FrequencyResponseEstimate {
  // Parallel arrays, one entry per bin f_m = m fs / L, m = 1..floor(L/2).
  std::vector<double> frequency_Hz;
  std::vector<double> w_rad_s;                  // 2 pi f
  std::vector<std::complex<double>> response;   // H1, output per input
  std::vector<double> coherence;                // gamma^2 in [0, 1]
  std::vector<double> input_psd;                // [input^2 / Hz]
  std::vector<double> output_psd;               // [output^2 / Hz]
  // Sample standard deviation of |H1_r| over the records; empty for one
  // record.
  std::vector<double> magnitude_std;
  int section_samples = 0;   // L
  int section_step = 0;      // L - overlap samples
  int sections_per_record = 0;
  int records = 0;
  double sample_rate_Hz = 0.0;
};

// One record: input x (e.g. voltage [V]) and output y (e.g. deflection
// [mm]) sampled together at options.sample_rate_Hz.
FrequencyResponseEstimate EstimateFrequencyResponse(const std::vector<double>& input,
                                                    const std::vector<double>& output,
                                                    const WelchOptions& options = {});

// Repeated experiments: inputs[r] and outputs[r] are record r; all records
// must have the same length.
FrequencyResponseEstimate EstimateFrequencyResponse(
    const std::vector<std::vector<double>>& inputs,
    const std::vector<std::vector<double>>& outputs, const WelchOptions& options = {});

}  // namespace ipmc
