// One IPMC link's loop (paper section 5.2) in the frequency domain and in
// the time domain: what `ipmc-swim bode` and `ipmc-swim step` compute
// (sim/cli/analysis_commands.h describes both in full), as functions that
// return the numbers instead of printing them.
//
//  - Bode: open loop L = C x P_link with the exact fractional plant
//    P = s^-0.5 G (sim/linear/ipmc_link_model.h, LinkResponseExact),
//    its gain crossover, phase and gain margins searched over
//    [1e-4, 1e5] rad/s, the controller and the plant at 5 rad/s, and the
//    columns of bode.csv (plant, controller, open loop, and the reference
//    model's open loop (5/s)^1.16 of eq. 8, each in dB and unwrapped deg).
//  - Step: each link's closed-loop unit step (1 mm) with the plant's s^-0.5
//    (and the fractional controller's s^-lambda) as 20 Oustaloup pairs on
//    [1e-5, 1e5] rad/s, its step metrics from a record long enough to
//    determine them, and J of eq. 11 against the reference model over the
//    horizon.
//
// Option values are checked by field: every error is a FieldError
// "COMMAND: FIELD must be ..., got ..." naming the option's field (the
// option tables below; the command line puts its flag in its place).
#pragma once

#include <complex>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "controllers/closed_loop.h"
#include "controllers/fractional_integrator.h"
#include "sim/linear/frequency_response.h"
#include "controllers/pid.h"
#include "sim/linear/ipmc_link_model.h"
#include "sim/core/scenario.h"
#include "sim/io/option_table.h"

namespace ipmc {

// Gains of the two controller families (defaults: eq. 12 and eq. 14, the
// controllers' own defaults).
struct ControllerGains {
  double kp = PidController::Config{}.kp;               // [V/mm]
  double ki = PidController::Config{}.ki;               // [V/(mm s)]
  double kd = PidController::Config{}.kd;               // [V s/mm]
  double gain = FractionalIntegrator::Config{}.gain;    // K [V/(mm s^lambda)]
  double order = FractionalIntegrator::Config{}.order;  // lambda
  double derivative_filter_s = 0.0;                     // PID's Tf [s] (0: ideal)
};

// Whether the caller gave an option explicitly, by field ("kp"; OptionGiven,
// sim/io/option_table.h): an option the chosen controller does not take is
// an error rather than ignored.

// Throws FieldError "COMMAND: links must be ..." unless
// `links` is a non-empty list of distinct links 1..max_links (Table 2's
// three, or the links of a plant or gains file; every command that
// chooses links takes them as links).
void ValidateLinkList(const std::string& command, const std::vector<int>& links,
                      int max_links = 3);

// ------------------------------------------------------------------ bode ---

struct BodeSpec {
  int link = 3;                                  // 1..3 (Table 2), or 1..n of a plant file
  std::string plant = "g1";                      // g1 | g2
  // pid | fractional | fractional-eq15 | fractional-oustaloup | none
  std::string controller;
  ControllerGains gains;
  int oustaloup_n = 4;                           // fractional-oustaloup
  std::vector<double> band_rad_s = {1e-3, 1e2};  // fractional-oustaloup
  double w_min_rad_s = 1e-2;                     // bode.csv grid
  double w_max_rad_s = 1e3;
  int points_per_decade = 100;
  // The link's own plant and where it came from (a plant file), in place
  // of Table 2's; its own gains from a gains file replace `gains`.
  std::optional<IpmcLinkParams> own_plant;
  std::string plant_source, gains_source;
};

// Throws FieldError naming `command` and the field.
void ValidateBodeSpec(const std::string& command, const BodeSpec& spec, const OptionGiven& given);

struct BodeAnalysis {
  FrequencyFunction plant, controller, loop;
  std::string controller_description, plant_description;
  MarginSearch search;
  StabilityMargins margins;
  double design_frequency_rad_s = 5.0;  // the reference model's crossover
  std::complex<double> controller_at_design, plant_at_design;
};

// The loop of a validated spec.
BodeAnalysis AnalyseBode(const BodeSpec& spec);

// bode.csv's columns on the spec's grid.
struct BodeColumns {
  BodeData plant, controller, open_loop, reference_open_loop;
};
BodeColumns ComputeBodeColumns(const BodeAnalysis& analysis, const BodeSpec& spec);
std::string BodeCsv(const BodeColumns& columns);

// Writes one response as "w_rad_s,magnitude_dB,phase_deg" and one row per
// point (17 significant digits) to a temporary file beside `path`, then
// renames it to `path`, so readers never see a partial file. Throws
// std::invalid_argument if the arrays differ in length and
// std::runtime_error naming the file on any I/O failure.
void WriteBodeCsv(const BodeData& bode, const std::filesystem::path& path);

// ------------------------------------------------------------------ step ---

struct StepSpec {
  std::string controller;            // pid | fractional
  std::string plant = "g1";          // g1 | g2
  std::vector<int> links = {1, 2, 3};
  ControllerGains gains;
  double horizon_s = 10.0;           // step.csv and J of eq. 11
  double max_horizon_s = 300.0;      // longest record for the step metrics
  double sample_rate_Hz = 1000.0;
  bool no_clamp = false;
  double v_max_V = 6.0;
  // Each link's own plant (a plant file's, link q at q - 1) in place of
  // Table 2's, and own gains (a gains file's) in place of `gains`; empty:
  // none. The sources name them in the descriptions.
  std::vector<IpmcLinkParams> own_plants;
  std::vector<ControllerGains> link_gains;
  std::string plant_source, gains_source;
  // A bench: each link's step also on this scenario's multibody simulation
  // (its model, plants, time step and fluid), with the spec's controllers
  // on every link, the stepped link's reference 1 mm from t = 0 and the
  // others' 0 (StepClosedLoop with these references), over the horizon.
  std::optional<ScenarioConfig> bench;
};

// Throws FieldError naming `command` and the field.
void ValidateStepSpec(const std::string& command, const StepSpec& spec, const OptionGiven& given);

struct LinkStep {
  int link = 0;
  ClosedLoopResponse response;  // the whole record (record_s = its last time)
  StepMetrics metrics;
  StepRecordStatus status = StepRecordStatus::kDetermined;
  double max_abs_control_V = 0;
  double cost = 0;              // J of eq. 11 over the horizon
  // Table 5's indices (TrackingIndices, the rectangle rule at the sample
  // rate, as `run` and `table5` compute them) of the step's error
  // e = 1 mm - y over the horizon's samples t_k = k T < horizon_s.
  TrackingIndices indices;
};

struct StepAnalysis {
  std::vector<LinkStep> links;           // in the spec's order
  // With a bench: each link's step on it, in the same order (record_s the
  // horizon: the metrics are those the horizon determines).
  std::vector<LinkStep> bench;
  std::vector<double> time_s;            // the horizon's grid (step.csv's rows)
  std::vector<double> reference;         // the reference model on it
  StepMetrics reference_metrics;         // with its exact first peak
  double metrics_horizon_s = 0;          // the longest record allowed
  std::string controller_description;
  double settling_band = 0.02;
  int oustaloup_pairs = 20;              // the accurate realisation's
  double band_low_rad_s = 1e-5, band_high_rad_s = 1e5;
};

// The steps of a validated spec.
StepAnalysis AnalyseStep(const StepSpec& spec);
// step.csv: time_s, reference_model, y_link<q>, u_link<q> over the horizon.
std::string StepCsv(const StepAnalysis& analysis);

// ------------------------------------------------------ the commands ---

// `bode` as both front ends run it: the links analysed in turn, and the
// output folder (one link's bode.csv and bode.json).
struct BodeCommand : BodeSpec {
  std::vector<int> links = {1, 2, 3};
  std::string plant_file;  // identify's plant.toml: each link's own plant
  std::string gains_file;  // design's gains.toml: each link's own gains
  std::string out;  // "": no files
};
struct BodeLink {
  BodeSpec spec;  // with its link
  BodeAnalysis analysis;
  BodeColumns columns;
};
const OptionTable<BodeCommand>& BodeOptions();
// Checks every link before the first is analysed, and `out` (one link, a
// writable folder); then analyses and writes OUT/bode.csv and
// OUT/bode.json together. Throws FieldError naming the field.
std::vector<BodeLink> RunBodeCommand(const BodeCommand& command, const OptionGiven& given);

// `step` as both front ends run it, with OUT/step.csv and OUT/step.json.
struct StepCommand : StepSpec {
  std::string bench_scenario;  // StepSpec::bench's file ("": no bench)
  std::string plant_file;  // identify's plant.toml: each link's own plant
  std::string gains_file;  // design's gains.toml: each link's own gains
  std::string out;  // "": no files
};
const OptionTable<StepCommand>& StepOptions();
StepAnalysis RunStepCommand(const StepCommand& command, const OptionGiven& given);

}  // namespace ipmc
