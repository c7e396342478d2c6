// The analysis subcommands of ipmc-swim: the paper's controller design
// (section 5.2) checked in the frequency domain ("bode") and in the time
// domain ("step"), one IPMC link at a time.
//
//   ipmc-swim bode --controller pid|fractional|fractional-eq15|
//                  fractional-oustaloup|none [--links 1,2,3] [--plant g1|g2] ...
// For each link in --links, the open loop L = C x P_link with the exact fractional plant
// P = s^-0.5 G (plugin/actuators/ipmc_link_model.h, LinkResponseExact). Prints the
// gain crossover, phase margin and gain margin (or "no finite gain
// margin") of L, searched over [1e-4, 1e5] rad/s (ComputeMargins'
// defaults), and the controller's and the plant's gain and phase at the
// reference model's crossover, 5 rad/s. Controllers:
//  - pid: Kp + Ki/s + Kd s (eq. 10; defaults eq. 12, ideal derivative);
//  - fractional: K / s^lambda, exact (eq. 13; defaults eq. 14);
//  - fractional-oustaloup: K / s^lambda through its Oustaloup realisation
//    (--oustaloup-pairs N on a band; defaults N = 4 on [1e-3, 1e2] rad/s, as eq. 15);
//  - fractional-eq15: the paper's printed eq. 15, a ratio of quartics;
//  - none: C = 1 (the plant alone).
// --out DIR (with one link) writes DIR/bode.csv on the --w-min..--w-max grid: w_rad_s and
// dB/deg pairs for the plant, the controller, the open loop and the
// reference model's open loop (5/s)^1.16 (eq. 8). Phases are unwrapped
// along increasing w.
//
//   ipmc-swim step --controller pid|fractional [--links 1,2,3] ...
// Unit step (1 mm) of each link's closed loop (unity feedback, controller
// sampled at --sample-rate-hz, clamped to +-V_max unless --no-clamp; see
// controllers/closed_loop.h). The plant's s^-0.5 is realised accurately by
// 20 Oustaloup pairs on [1e-5, 1e5] rad/s, and so is the fractional
// controller's s^-lambda. Prints per link the overshoot, 10-90 % rise
// time, peak, 2 % settling time, largest |u| and J of eq. 11 against the
// reference model over the horizon (--horizon-s, 10 s by default), and the
// reference model's own step metrics. The step metrics must not depend on
// where the record stops: each link's simulation goes on past the
// horizon, a horizon at a time, until its metrics are determined
// (controllers/closed_loop.h, CheckStepRecord: 90 % reached, the peak
// passed, inside the settling band for at least half the record), at most
// to --max-horizon-s (300 s) and 1e6 samples; the record's length is
// printed (record_s), and a metric it still does not determine is marked
// '*' and named below the table. --out DIR writes DIR/step.csv over the
// horizon: time_s, reference_model, then y_link<q> [mm] and u_link<q> [V]
// for each link.
//
// Bad option values throw std::invalid_argument with a one-line message
// naming the option; nothing is written unless the whole analysis
// succeeded, and each file is written atomically.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "sim/identify/loop_analysis.h"

namespace ipmc {

// The computations are in sim/identify/loop_analysis.h; the options here
// add the output directory.
struct BodeArgs : BodeSpec {
  std::vector<int> links = {1, 2, 3};  // each analysed in turn (spec.link)
  std::string out_dir;                 // bode.csv of one link
};

struct StepArgs : StepSpec {
  std::string out_dir;
};

struct AnalysisArgs {
  BodeArgs bode;
  StepArgs step;
};

// Adds subcommands "bode" and "step" to app, storing options in args.
void AddAnalysisCommands(CLI::App& app, AnalysisArgs& args);

// Runs the analysis subcommand that app parsed; returns its exit code, or
// -1 if none of them was chosen. Throws std::invalid_argument for bad
// option values and std::runtime_error for output failures.
int RunAnalysisCommand(const CLI::App& app, const AnalysisArgs& args);

}  // namespace ipmc
