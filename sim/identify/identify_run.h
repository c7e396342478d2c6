// Identification and design as `ipmc-swim identify` and `ipmc-swim design`
// compute them (sim/cli/identify_command.h describes both), as functions
// that return the numbers instead of printing them, and the pieces the
// pipeline shares with them.
//
//  - IdentifyRecord: one input/output record sampled at a fixed rate,
//    Welch's frequency response (sim/identify/welch.h) and the Levy fits of
//    G1 and G2 over a band (sim/identify/levy.h), P = s^-0.5 G.
//  - DesignLink: on Table 2's link model, the analytic fractional
//    integrator K/s^lambda for a crossover and phase margin with the
//    margins of its exact open loop, and the PID tuned by Nelder-Mead
//    against the reference model over a horizon (sim/identify/controller_design.h).
//
// Option values are checked by field: every error is a FieldError
// "COMMAND: FIELD must be ..., got ..." naming the option's field.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/linear/frequency_response.h"
#include "sim/linear/ipmc_link_model.h"
#include "sim/identify/controller_design.h"
#include "sim/identify/levy.h"
#include "sim/identify/welch.h"
#include "sim/io/option_table.h"

namespace ipmc {

// --------------------------------------------------------------- identify ---

struct IdentifySpec {
  std::string data_path;      // the record's file (or name), for messages
  std::string input_column;   // [V]
  std::string output_column;  // [mm]
  double sample_rate_Hz = 1000.0;
  std::vector<double> band_rad_s = {0.2, 50.0};
  // Bins of the band drive the fits only where the record excites them and
  // input and output are coherent: coherence >= min_coherence and the
  // input's spectral density within min_excitation_dB of its largest in
  // the band. So a chirp, broadband noise, stepped sines or multisines
  // each give their excited bins, and a bin between a multisine's lines or
  // beyond a chirp's end does not pull the fit.
  double min_coherence = 0.8;       // in [0, 1)
  double min_excitation_dB = 30.0;  // > 0
  // The fit handed to a run (plant.toml): g1 or g2.
  std::string plant = "g1";

  // The sample rate, the band, the thresholds and distinct columns; throws
  // std::invalid_argument naming the field.
  void Validate() const;
};

// How far the fit can be trusted: which bins of the band drove it, and
// warnings for a poor fit (R^2 of the handed fit below kPoorFitR2, fewer
// than half the band's bins used, an unstable fit).
struct FitCheck {
  int band_bins = 0;        // Welch bins inside the band
  int used_bins = 0;        // of which drove the fits
  int low_coherence = 0;    // left out: coherence below min_coherence
  int low_excitation = 0;   // left out: input below min_excitation_dB (and not counted above)
  double mean_coherence = 0;  // over the used bins
  double r_squared = 0;       // of the handed fit (spec.plant)
  std::vector<std::string> warnings;  // one line each; empty: a good fit
};
// R^2 of a fit below this is a poor fit.
constexpr double kPoorFitR2 = 0.95;

struct RecordIdentification {
  std::size_t samples = 0;  // of the record
  LevyOptions levy;  // the band
  FrequencyResponseEstimate estimate;
  LinkIdentification id;
  FitCheck check;
  // Links 2..n from IdentifyCommand::link_records, in order.
  std::vector<RecordIdentification> other_links;
};

// The fit spec.plant names (g1 or g2).
const LinkModelFit& HandedFit(const IdentifySpec& spec, const RecordIdentification& result);

// plant.toml: the handed fit as the scenario keys [plant] (model, a0, b1
// and b2 or alpha) for every link, or with other_links the fits of links
// 1..n as plant.link_*, which a scenario includes (`include`) to run the
// identified plants.
std::string PlantToml(const IdentifySpec& spec, const RecordIdentification& result);

// Identifies one record: `time_s` (may be null) must be spaced at the
// spec's sample rate within 0.1 %, and the record long enough for Welch's
// first bin to reach the band's low end. Throws std::invalid_argument
// naming the option or the record.
RecordIdentification IdentifyRecord(const IdentifySpec& spec, const std::vector<double>& input,
                                    const std::vector<double>& output,
                                    const std::vector<double>* time_s);

// identification.json: the spec, the band, Welch's set-up and both fits.
nlohmann::json IdentificationJson(const IdentifySpec& spec, const RecordIdentification& result);

// response.csv: w_rad_s, frequency_Hz, coherence, measured re/im, measured,
// P1 and P2 in dB and unwrapped deg, in_band (inside the fits' band).
std::string ResponseCsv(const FrequencyResponseEstimate& estimate, const LinkIdentification& id);

// The band LOW,HIGH of `command` as Levy options; throws
// std::invalid_argument naming band_rad_s.
LevyOptions BandOptions(const std::string& command, const std::vector<double>& band);

// ----------------------------------------------------------------- design ---

// phase_margin_deg in (0, 180); throws std::invalid_argument naming it.
void RequirePhaseMargin(const std::string& command, double value);

// Tuning options for a reference model, horizon and loop rate given as
// `command`'s options; throws std::invalid_argument naming the option.
PidTuningOptions TuningOptions(const std::string& command, double crossover_rad_s,
                               double reference_order, double horizon_s, double sample_rate_Hz);

struct DesignSpec {
  int link = 3;                  // 1..3 (Table 2)
  std::string plant = "g1";      // g1 | g2
  double crossover_rad_s = 5.0;
  double phase_margin_deg = 75.0;
  double reference_order = 1.16;
  double horizon_s = 2.0;
  // The tuning loop's PID rate: the 1 kHz the controllers run at (a
  // scenario's controller.sample_rate_Hz with design --scenario).
  double sample_rate_Hz = 1000.0;
  double derivative_filter_s = 0.0;  // the PID's Tf in the tuning loop [s]
};

struct LinkDesign {
  int link = 0;                  // 1-based
  IpmcLinkParams params;         // the plant designed for
  PidTuningOptions tuning;
  FractionalLoopDesign fractional;
  double paper_cost = 0;         // J of eq. 11 at eq. 12's gains (PidGains{})
  PidTuningResult tuned;
  StabilityMargins pid_margins;  // tuned PID, continuous, on the exact plant
  double tuning_s = 0;           // wall time of the PID tuning
  // The derivative's RMS noise voltage at the tuned Kd and the tuning's Tf
  // for DesignCommand::sensor_noise_mm (DerivativeNoiseRms_V); 0 without.
  double derivative_noise_V = 0;
};

// Validates (std::invalid_argument naming the field) and designs for
// `own_plant`, or Table 2's row spec.link of spec.plant if null;
// check_stop, if given, is called before each evaluation of the PID
// tuning's J (PidTuningOptions::check_stop) and may throw to stop it.
LinkDesign DesignLink(const DesignSpec& spec, const IpmcLinkParams* own_plant = nullptr,
                      const std::function<void()>& check_stop = {});

// ------------------------------------------------------ the commands ---

// `identify` as both front ends run it: the record's columns and rate,
// the band, and the output folder (response.csv, identification.json).
struct IdentifyCommand : IdentifySpec {
  // Records of links 2..n, one per link, with the record's columns, rate
  // and band: plant.toml then holds one plant per link.
  std::vector<std::string> link_records;
  std::string out;  // "": no files
};
const OptionTable<IdentifyCommand>& IdentifyOptions();
// Identifies the record (IdentifyRecord) and writes OUT/response.csv,
// OUT/identification.json and OUT/plant.toml together.
RecordIdentification RunIdentifyCommand(const IdentifyCommand& command,
                                        const std::vector<double>& input,
                                        const std::vector<double>& output,
                                        const std::vector<double>* time_s);

// The same on the record in the file command.data_path (a CSV with a
// header row, sim/io/csv.h; a time_s column, if present, is checked
// against the rate). Throws InputError naming the file, line and column
// for bad data.
RecordIdentification RunIdentifyCommandOnFile(const IdentifyCommand& command);

// `design` as both front ends run it: the links designed in turn.
struct DesignCommand : DesignSpec {
  std::vector<int> links = {1, 2, 3};
  // A TOML file of [plant] scenario keys (the plant.toml identify writes):
  // each link is designed for the plant those keys give it.
  std::string plant_file;
  // A scenario: each of its links is designed for the plant its run gives
  // the link, at its controller's sample rate.
  std::string scenario;
  // The PID's derivative filter as a bandwidth w_f: Tf = 1 / w_f, in the
  // tuning loop and in gains.toml (0: the ideal derivative).
  double derivative_bandwidth_rad_s = 0.0;
  // Or from the sensor's noise: the RMS noise of the measured deflection
  // [mm], white per sample (0: none), and the bound on the derivative's
  // noise voltage [V RMS]; Tf is the smallest (to 1 %) that keeps every
  // link's derivative within the bound (DerivativeNoiseRms_V) at the Kd
  // tuned with it.
  double sensor_noise_mm = 0.0;
  double derivative_noise_V = 0.06;  // 1 % of the paper's 6 V clamp
  // gains.toml: the tuned PIDs as controller.link_kp, link_ki and link_kd
  // (links 1..n in order), which a scenario includes.
  std::string out;
};
const OptionTable<DesignCommand>& DesignOptions();
// Checks the links and out first, then designs each (DesignLink, with
// check_stop; a stop it throws writes nothing) and writes out. `given`
// tells which options the caller set: with a scenario or a plant file the
// links are every link of it unless `links` is given, and with a scenario
// the sample rate is its controller's unless `sample_rate_Hz` is given.
std::vector<LinkDesign> RunDesignCommand(const DesignCommand& command,
                                         const OptionGiven& given = {},
                                         const std::function<void()>& check_stop = {});
// gains.toml of the designs of links 1..n in order, with their Tf.
std::string GainsToml(const DesignCommand& command, const std::vector<LinkDesign>& designs);

}  // namespace ipmc
