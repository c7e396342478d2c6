// One link identified from a bench record (paper sections 4.1 and 4.2), as
// the identification pipeline does it: R copies of the record that differ
// only by white Gaussian measurement noise added to the output (the
// simulator is deterministic, so repeats differ by nothing else), their
// Welch spectra pooled (sim/identify/welch.h), and the Levy fits of G1 and
// G2 over the band (sim/identify/levy.h). If the record is too short for
// the band's low end, the band starts at the first Welch bin instead, and
// a note says so.
#pragma once

#include <string>
#include <vector>

#include "sim/identify/levy.h"
#include "sim/identify/welch.h"

namespace ipmc {

struct BenchIdentificationOptions {
  int repeats = 1;                 // R >= 1
  double noise_mm = 0.0;           // standard deviation [mm], >= 0; 0: no noise
  unsigned seed = 1;               // record r of stream s: mt19937_64(seed + 1000003 s + r)
  double sample_rate_Hz = 1000.0;  // of the record
  LevyOptions band;
};

struct BenchIdentification {
  FrequencyResponseEstimate estimate;
  LevyOptions levy;       // the band fitted
  std::string band_note;  // why it differs from the options' band ("" if it does not)
  LinkIdentification id;
};

// Identifies the link from `input_V` and `output_mm` (one record).
// `stream` numbers the noise (one stream per link). Throws
// std::invalid_argument for data Welch or Levy refuses.
BenchIdentification IdentifyBenchRecord(const std::vector<double>& input_V,
                                        const std::vector<double>& output_mm,
                                        const BenchIdentificationOptions& options,
                                        unsigned long long stream);

// Raises the band's low end to the first Welch bin if the record is too
// short for it; returns a note saying so (empty if not needed).
std::string FitBandToData(LevyOptions& levy, const FrequencyResponseEstimate& estimate);

}  // namespace ipmc
