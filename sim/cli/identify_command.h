// The identification subcommands of ipmc-swim (paper sections 4.1, 4.2 and
// 5.2): frequency response from bench data (sim/identify/welch.h), Levy fits of G1
// and G2 (sim/identify/levy.h), and the controller design on an identified link
// (sim/identify/controller_design.h).
//
//   ipmc-swim identify DATA.csv --input voltage1_V --output relative3_mm
//       [--sample-rate-hz 1000] [--band-rad-s 0.2,50] [--out DIR]
// DATA.csv: a header row naming the columns (the bench CSV: time_s,
// voltage1_V, relative1_mm, tip1_lateral_mm, free1_mm, voltage2_V, ...),
// then one row of numbers per sample. The two named columns are the input
// [V] and the output [mm]; if a time_s column is present its spacing must
// agree with --sample-rate-hz (0.1 %). Prints the Welch set-up, the G1 and
// G2 fits (P = s^-0.5 G) and Table 3's indices. --out DIR writes
// DIR/response.csv (w_rad_s, frequency_Hz, coherence, measured re/im,
// measured, P1 and P2 in dB and unwrapped deg, in_band) and
// DIR/identification.json (the parameters and indices).
//
//   ipmc-swim design [--links 1,2,3] [--plant g1|g2] [--crossover-rad-s 5]
//       [--phase-margin-deg 75] [--reference-order 1.16] [--horizon-s 2]
//       [--sample-rate-hz 10000]
// For each link, on its Table 2 model: the analytic fractional integrator K/s^lambda
// for the crossover and phase margin, with the margins of its exact open
// loop; the PID tuned by Nelder-Mead against the reference model
// 1/((s/w_c)^gamma + 1) over the horizon, with J of eq. 11 at the paper's
// gains (eq. 12) and at the tuned gains, per start.
//
//   ipmc-swim pipeline [--out DIR] [--duration-s 200] [--repeats 1]
//       [--noise-mm 0] [--drive each|first] [--model M] ...
// The bench chirp of section 4.1 (3 V, 0.1 to 200 Hz, 1 kHz) on the
// simulated clamped flagellum, then Welch, Levy and both designs for link
// 3 on its identified G1. --drive each (default) drives each link in turn
// (three runs, in parallel threads) and identifies its relative tip
// deflection L_q sin(theta_q), so that every identified model can be
// compared with the parameters the simulator was given; --drive first is
// the paper's experiment: link 1 alone is driven and each link's tip is
// measured laterally (the laser). The simulator is deterministic, so
// --repeats R records differ only by the added measurement noise (white,
// Gaussian, --noise-mm standard deviation, seeded by --seed); the Welch
// spectra of the R records are pooled. If the record is too short for the
// band's low end, the band starts at the first Welch bin (said in the
// report). Prints the Markdown report; --out DIR also writes
// DIR/report.md and DIR/response_link<q>.csv.
//
// Bad option values throw std::invalid_argument with one line naming the
// option; bad data (read by sim/io/csv.h) throws InputError
// (plugin/base/error.h) naming the file, line and column. Nothing is written
// unless the command succeeded, and each file is written atomically.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "sim/identify/identify_run.h"

namespace ipmc {

struct IdentifyArgs {
  // The computations are in sim/identify/identify_run.h.
  struct Identify : IdentifySpec {
    std::string out_dir;
  } identify;

  struct Design : DesignSpec {
    std::vector<int> links = {1, 2, 3};  // each designed in turn (spec.link)
  } design;

  struct Pipeline {
    std::string model_path;  // empty: models/flagellum3_clamped.xml
    std::string drive = "each";
    double duration_s = 200.0;
    double amplitude_v = 3.0;
    double f0_hz = 0.1;
    double f1_hz = 200.0;
    int repeats = 1;
    double noise_mm = 0.0;
    unsigned seed = 1;
    std::vector<double> band_rad_s = {0.2, 50.0};
    double crossover_rad_s = 5.0;
    double phase_margin_deg = 75.0;
    double horizon_s = 2.0;
    std::string out_dir;
  } pipeline;
};

// Adds subcommands "identify", "design" and "pipeline" to app.
void AddIdentifyCommands(CLI::App& app, IdentifyArgs& args);

// Runs the subcommand app parsed; returns its exit code, or -1 if none of
// these was chosen. Throws std::invalid_argument for bad options,
// InputError for bad data and std::runtime_error for simulation or output
// failures.
int RunIdentifyCommand(const CLI::App& app, const IdentifyArgs& args);

}  // namespace ipmc
