// One line of text for each result of identification and design, as the
// identify, design and pipeline commands print them and the pipeline's
// report holds them.
#pragma once

#include <string>

#include "controllers/fractional_integrator.h"
#include "sim/linear/frequency_response.h"
#include "sim/identify/controller_design.h"
#include "sim/identify/levy.h"
#include "sim/identify/welch.h"

namespace ipmc {

// The paper's eq. 12 and eq. 14 (the controllers' defaults), for comparison.
inline const PidGains kPaperPid{};
inline const FractionalIntegrator::Config kPaperFractional{};

// "stable" / "UNSTABLE".
std::string StabilityText(const LinkModelFit& fit);
// G1's parameters (and zeta, w_n when both b1, b2 > 0), stability.
std::string DescribeG1(const LinkModelFit& fit);
// G2's parameters, stability, and how many orders were stable.
std::string DescribeG2(const LinkModelFit& fit, const LinkIdentification& id);
// Welch's set-up: records, sections, window, resolution.
std::string WelchDescription(const FrequencyResponseEstimate& e);
// The mean coherence over the band points of a fit.
double MeanCoherenceInBand(const FrequencyResponseEstimate& e, const FitIndices& indices);
// Crossover, phase margin and gain margin (or their absence).
std::string MarginsText(const StabilityMargins& m);
// "C(s) = Kp + Ki/s + Kd s".
std::string PidText(const PidGains& g);

}  // namespace ipmc
