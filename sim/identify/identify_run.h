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

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "controllers/linear/frequency_response.h"
#include "plugin/actuators/ipmc_link_model.h"
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

  // The sample rate, the band and distinct columns; throws
  // std::invalid_argument naming the field.
  void Validate() const;
};

struct RecordIdentification {
  std::size_t samples = 0;  // of the record
  LevyOptions levy;  // the band
  FrequencyResponseEstimate estimate;
  LinkIdentification id;
};

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
  double sample_rate_Hz = 10000.0;
};

struct LinkDesign {
  IpmcLinkParams params;         // the plant designed for
  PidTuningOptions tuning;
  FractionalLoopDesign fractional;
  double paper_cost = 0;         // J of eq. 11 at eq. 12's gains (PidGains{})
  PidTuningResult tuned;
  StabilityMargins pid_margins;  // tuned PID, continuous, on the exact plant
  double tuning_s = 0;           // wall time of the PID tuning
};

// Validates (std::invalid_argument naming the field) and designs.
LinkDesign DesignLink(const DesignSpec& spec);

// ------------------------------------------------------ the commands ---

// `identify` as both front ends run it: the record's columns and rate,
// the band, and the output folder (response.csv, identification.json).
struct IdentifyCommand : IdentifySpec {
  std::string out;  // "": no files
};
const OptionTable<IdentifyCommand>& IdentifyOptions();
// Identifies the record (IdentifyRecord) and writes OUT/response.csv and
// OUT/identification.json together.
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
};
const OptionTable<DesignCommand>& DesignOptions();
// Checks the links first, then designs each (DesignLink).
std::vector<LinkDesign> RunDesignCommand(const DesignCommand& command);

}  // namespace ipmc
