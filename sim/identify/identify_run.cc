#include "sim/identify/identify_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <utility>

#include "controllers/reference_model.h"
#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/identify/key_files.h"
#include "sim/identify/loop_analysis.h"
#include "sim/io/files.h"
#include "sim/core/key_builder.h"
#include "sim/core/model_generator.h"
#include "sim/core/scenario.h"
#include "sim/core/scenario_simulation.h"

namespace ipmc {
namespace {

using Complex = std::complex<double>;
using Clock = std::chrono::steady_clock;

constexpr char kIdentifyCommand[] = "identify";
constexpr char kDesignCommand[] = "design";

// The time_s column must give the sample rate to this relative tolerance.
constexpr double kSampleRateTolerance = 1e-3;
// And each of its steps must be one sample period to within this fraction
// of a period (a record written at 3 decimals of a 1 ms period is exact to
// float rounding; a missing sample is a step of 2 periods).
constexpr double kTimeStepTolerance = 0.25;
constexpr double kMaxTuningSamples = 1e7;

std::vector<double> UnwrappedPhaseDeg(const std::vector<Complex>& values) {
  std::vector<double> phase(values.size());
  double offset = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double raw = std::arg(values[i]) * 180 / kPi;
    if (i > 0) {
      const double previous = phase[i - 1] - offset;
      if (raw - previous > 180) offset -= 360;
      if (raw - previous < -180) offset += 360;
    }
    phase[i] = raw + offset;
  }
  return phase;
}

nlohmann::json IndicesJson(const FitIndices& i) {
  return {{"J", i.levy_cost},         {"MSE", i.mse},
          {"MAD", i.mad},             {"MD", i.max_deviation},
          {"R2", i.r_squared},        {"points", i.points},
          {"w_first_rad_s", i.w_first_rad_s}, {"w_last_rad_s", i.w_last_rad_s}};
}

nlohmann::json FitJson(const LinkModelFit& fit) {
  nlohmann::json json = {{"a0_mm_per_V", fit.params.a0_mm_per_V},
                         {"b1", fit.params.b1},
                         {"stable", fit.stable},
                         {"indices", IndicesJson(fit.indices)}};
  if (fit.params.kind == IpmcModelKind::kG1) {
    json["b2_s2"] = fit.params.b2_s2;
  } else {
    json["alpha"] = fit.params.alpha;
  }
  return json;
}

double Seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

void RequirePhaseMargin(const std::string& command, double value) {
  if (!std::isfinite(value) || !(value > 0) || !(value < 180)) {
    ThrowOption(command, "phase_margin_deg", "in (0, 180)", FormatDouble(value));
  }
}

// --------------------------------------------------------------- identify ---

LevyOptions BandOptions(const std::string& command, const std::vector<double>& band) {
  if (band.size() != 2) {
    ThrowOption(command, "band_rad_s", "two values LOW,HIGH",
                std::to_string(band.size()) + " values");
  }
  if (!std::isfinite(band[0]) || !std::isfinite(band[1]) || !(band[0] > 0) ||
      !(band[1] > band[0])) {
    ThrowOption(command, "band_rad_s", "0 < LOW < HIGH",
                FormatDouble(band[0]) + "," + FormatDouble(band[1]));
  }
  LevyOptions options;
  options.w_low_rad_s = band[0];
  options.w_high_rad_s = band[1];
  return options;
}

void IdentifySpec::Validate() const {
  const std::string name = kIdentifyCommand;
  RequireFinitePositive(name, "sample_rate_Hz", sample_rate_Hz);
  BandOptions(name, band_rad_s);
  if (input_column == output_column) {
    ThrowOption(name, "output", "a column other than input", output_column);
  }
  if (!(min_coherence >= 0) || !(min_coherence < 1)) {
    ThrowOption(name, "min_coherence", "in [0, 1)", FormatDouble(min_coherence));
  }
  RequireFinitePositive(name, "min_excitation_dB", min_excitation_dB);
  if (plant != "g1" && plant != "g2") ThrowOption(name, "plant", "g1 or g2", plant);
}

namespace {

// Fewest bins a fit may rest on (G1 has three parameters).
constexpr int kMinFitBins = 4;

// The band's bins that drive the fits (FitCheck), and the counts.
struct FitBins {
  std::vector<double> w_rad_s;
  std::vector<Complex> response;
  FitCheck check;
};

FitBins SelectFitBins(const FrequencyResponseEstimate& e, const LevyOptions& band,
                      const IdentifySpec& spec) {
  FitBins bins;
  double most_psd = 0;
  for (std::size_t i = 0; i < e.w_rad_s.size(); ++i) {
    if (e.w_rad_s[i] >= band.w_low_rad_s && e.w_rad_s[i] <= band.w_high_rad_s) {
      most_psd = std::max(most_psd, e.input_psd[i]);
    }
  }
  const double least_psd = most_psd * std::pow(10.0, -spec.min_excitation_dB / 10);
  double coherence_sum = 0;
  for (std::size_t i = 0; i < e.w_rad_s.size(); ++i) {
    if (e.w_rad_s[i] < band.w_low_rad_s || e.w_rad_s[i] > band.w_high_rad_s) continue;
    ++bins.check.band_bins;
    if (e.coherence[i] < spec.min_coherence) {
      ++bins.check.low_coherence;
    } else if (e.input_psd[i] < least_psd) {
      ++bins.check.low_excitation;
    } else {
      bins.w_rad_s.push_back(e.w_rad_s[i]);
      bins.response.push_back(e.response[i]);
      coherence_sum += e.coherence[i];
    }
  }
  bins.check.used_bins = static_cast<int>(bins.w_rad_s.size());
  if (bins.check.used_bins > 0) bins.check.mean_coherence = coherence_sum / bins.check.used_bins;
  return bins;
}

// The warnings of a fit resting on `check`'s bins.
void JudgeFit(const IdentifySpec& spec, const LinkModelFit& fit, FitCheck* check) {
  check->r_squared = fit.indices.r_squared;
  const std::string name = spec.plant == "g2" ? "P2" : "P1";
  if (check->r_squared < kPoorFitR2) {
    check->warnings.push_back(FormatText("poor fit: %s has R^2 = %.4g (below %.4g)", name.c_str(),
                                         check->r_squared, kPoorFitR2));
  }
  if (2 * check->used_bins < check->band_bins) {
    check->warnings.push_back(FormatText(
        "only %d of the band's %d bins drove the fit (%d with coherence below %.4g, %d excited "
        "less than %.4g dB below the most): excite the band or narrow it",
        check->used_bins, check->band_bins, check->low_coherence, spec.min_coherence,
        check->low_excitation, spec.min_excitation_dB));
  }
  if (!fit.stable) check->warnings.push_back("the " + name + " fit is unstable");
}

}  // namespace

const LinkModelFit& HandedFit(const IdentifySpec& spec, const RecordIdentification& result) {
  return spec.plant == "g2" ? result.id.g2 : result.id.g1;
}

RecordIdentification IdentifyRecord(const IdentifySpec& spec, const std::vector<double>& input,
                                    const std::vector<double>& output,
                                    const std::vector<double>* time_s) {
  const std::string name = kIdentifyCommand;
  spec.Validate();
  RecordIdentification result;
  result.samples = input.size();
  result.levy = BandOptions(name, spec.band_rad_s);
  if (time_s && time_s->size() >= 2) {
    const std::vector<double>& t = *time_s;
    const double spacing = (t.back() - t.front()) / (t.size() - 1);
    if (!(spacing > 0) ||
        std::abs(spacing * spec.sample_rate_Hz - 1.0) > kSampleRateTolerance) {
      throw FieldError(
          name + ": sample_rate_Hz " + FormatDouble(spec.sample_rate_Hz) +
          " disagrees with the time_s column of " + spec.data_path + " (mean spacing " +
          FormatDouble(spacing) + " s, i.e. " + FormatDouble(1.0 / spacing) + " Hz)",
          "sample_rate_Hz", "the time_s column's rate");
    }
    // Evenly sampled: each row one sample period after the one before,
    // to within kTimeStepTolerance of a period (no gap, no step back).
    const double period_s = 1.0 / spec.sample_rate_Hz;
    for (size_t k = 1; k < t.size(); ++k) {
      const double step_s = t[k] - t[k - 1];
      if (std::abs(step_s - period_s) <= kTimeStepTolerance * period_s) continue;
      throw FieldError(name + ": the time_s column of " + spec.data_path + " " +
                           (step_s < 0 ? "runs backward" : step_s == 0 ? "repeats a time" : "jumps") + " at data row " +
                           std::to_string(k + 1) + " (t = " + FormatDouble(t[k]) + " s after " +
                           FormatDouble(t[k - 1]) + " s; every row must follow the one before by " +
                           FormatDouble(period_s) + " s)",
                       "time_s", "evenly sampled at sample_rate_Hz");
    }
  }
  for (const auto& [column, values] : {std::pair{spec.input_column, &input},
                                        std::pair{spec.output_column, &output}}) {
    const auto [low, high] = std::minmax_element(values->begin(), values->end());
    if (values->empty() || *low == *high) {
      throw std::invalid_argument(spec.data_path + ": column " + column +
                                  " is constant: no frequency response to identify");
    }
  }
  WelchOptions welch;
  welch.sample_rate_Hz = spec.sample_rate_Hz;
  try {
    result.estimate = EstimateFrequencyResponse(input, output, welch);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(spec.data_path + ": " + error.what());
  }
  if (result.levy.w_low_rad_s < result.estimate.w_rad_s.front()) {
    // Welch's first bin is 2 pi fs / L with L = N / 4.5.
    const double needed_s = 4.5 * kTwoPi / result.levy.w_low_rad_s;
    throw FieldError(FormatText(
        "%s: band_rad_s low end %.4g rad/s is below the first Welch bin %.4g rad/s of this "
        "%.4g s record (8 sections with 50 %% overlap reach it from about %.4g s of data)",
        name.c_str(), result.levy.w_low_rad_s, result.estimate.w_rad_s.front(),
        input.size() / spec.sample_rate_Hz, needed_s), "band_rad_s", "above the first Welch bin");
  }
  FitBins bins = SelectFitBins(result.estimate, result.levy, spec);
  if (bins.check.used_bins < kMinFitBins) {
    throw FieldError(FormatText("%s: %s has %d bins in band_rad_s [%.4g, %.4g] with coherence >= "
                                "%.4g and excitation within %.4g dB (at least %d needed)",
                                name.c_str(), spec.data_path.c_str(), bins.check.used_bins,
                                result.levy.w_low_rad_s, result.levy.w_high_rad_s,
                                spec.min_coherence, spec.min_excitation_dB, kMinFitBins),
                     "band_rad_s", "a band the record excites");
  }
  // The fits see only the used bins; their band is the bins' span (the
  // same points as the band when every bin is used).
  LevyOptions levy = result.levy;
  levy.w_low_rad_s = bins.w_rad_s.front();
  levy.w_high_rad_s = bins.w_rad_s.back();
  result.id = IdentifyLinkModels(bins.w_rad_s, bins.response, levy);
  result.check = std::move(bins.check);
  JudgeFit(spec, HandedFit(spec, result), &result.check);
  return result;
}

namespace {

nlohmann::json FitCheckJson(const IdentifySpec& spec, const FitCheck& check) {
  return {{"plant", spec.plant},
          {"min_coherence", spec.min_coherence},
          {"min_excitation_dB", spec.min_excitation_dB},
          {"band_bins", check.band_bins},
          {"used_bins", check.used_bins},
          {"low_coherence_bins", check.low_coherence},
          {"low_excitation_bins", check.low_excitation},
          {"mean_coherence", check.mean_coherence},
          {"r_squared", check.r_squared},
          {"poor_fit", !check.warnings.empty()},
          {"warnings", check.warnings}};
}

}  // namespace

nlohmann::json IdentificationJson(const IdentifySpec& spec, const RecordIdentification& result) {
  const FrequencyResponseEstimate& estimate = result.estimate;
  nlohmann::json links = nlohmann::json::array();
  for (const RecordIdentification& link : result.other_links) {
    links.push_back({{"g1", FitJson(link.id.g1)},
                     {"g2", FitJson(link.id.g2)},
                     {"fit_check", FitCheckJson(spec, link.check)}});
  }
  nlohmann::json json = {{"data", spec.data_path},
          {"input", spec.input_column},
          {"output", spec.output_column},
          {"sample_rate_Hz", spec.sample_rate_Hz},
          {"band_rad_s", {result.levy.w_low_rad_s, result.levy.w_high_rad_s}},
          {"welch",
           {{"records", estimate.records},
            {"sections", estimate.sections_per_record},
            {"section_samples", estimate.section_samples},
            {"section_step", estimate.section_step}}},
          {"g1", FitJson(result.id.g1)},
          {"g2", FitJson(result.id.g2)},
          {"fit_check", FitCheckJson(spec, result.check)}};
  // Links 2..n (identify --link-records), each from its own record.
  if (!links.empty()) json["other_links"] = links;
  return json;
}

std::string PlantToml(const IdentifySpec& spec, const RecordIdentification& result) {
  std::vector<const RecordIdentification*> links = {&result};
  for (const RecordIdentification& link : result.other_links) links.push_back(&link);
  bool poor = false;
  std::vector<double> a0, b1, b2_or_alpha;
  for (const RecordIdentification* link : links) {
    const IpmcLinkParams& p = HandedFit(spec, *link).params;
    a0.push_back(p.a0_mm_per_V);
    b1.push_back(p.b1);
    b2_or_alpha.push_back(spec.plant == "g2" ? p.alpha : p.b2_s2);
    poor = poor || !link->check.warnings.empty();
  }
  std::string text = FormatText(
      "# The plant%s ipmc-swim identify fitted to %s%s (input %s, output %s)\n"
      "# over [%.6g, %.6g] rad/s: R^2 = %.6g%s%s. A scenario takes %s with\n"
      "# include = [\"plant.toml\"].\n[plant]\nmodel = \"%s\"\n",
      links.size() > 1 ? "s" : "", spec.data_path.c_str(),
      links.size() > 1 ? " and the other links' records" : "", spec.input_column.c_str(),
      spec.output_column.c_str(), result.levy.w_low_rad_s, result.levy.w_high_rad_s,
      result.check.r_squared, links.size() > 1 ? " on link 1" : "",
      poor ? " (a poor fit: see identification.json)" : "",
      links.size() > 1 ? "one per link" : "it for every link", spec.plant.c_str());
  const char* last = spec.plant == "g2" ? "alpha" : "b2_s2";
  if (links.size() == 1) {
    return text + "a0_mm_per_V = " + FormatShortest(a0[0]) + "\nb1 = " + FormatShortest(b1[0]) +
           "\n" + last + " = " + FormatShortest(b2_or_alpha[0]) + "\n";
  }
  return text + "link_a0_mm_per_V = " + *TomlFloats(a0) + "\nlink_b1 = " + *TomlFloats(b1) +
         "\nlink_" + last + " = " + *TomlFloats(b2_or_alpha) + "\n";
}

std::string ResponseCsv(const FrequencyResponseEstimate& e, const LinkIdentification& id) {
  std::vector<Complex> p1, p2;
  for (double w : e.w_rad_s) {
    p1.push_back(FittedResponse(id.g1.params, w));
    p2.push_back(FittedResponse(id.g2.params, w));
  }
  const std::vector<double> measured_deg = UnwrappedPhaseDeg(e.response);
  const std::vector<double> p1_deg = UnwrappedPhaseDeg(p1);
  const std::vector<double> p2_deg = UnwrappedPhaseDeg(p2);
  CsvWriter csv(10);
  csv.Add(columns::kFrequency).Add(columns::kFrequencyHz).Add(columns::kCoherence);
  csv.Add(columns::kMeasuredRe).Add(columns::kMeasuredIm);
  for (const char* curve : {columns::kMeasuredCurve, columns::kP1Curve, columns::kP2Curve}) {
    csv.Add(columns::MagnitudeDb(curve)).Add(columns::PhaseDeg(curve));
  }
  csv.Add(columns::kInBand).EndRow();
  for (std::size_t i = 0; i < e.w_rad_s.size(); ++i) {
    const double w = e.w_rad_s[i];
    const bool in_band =
        w >= id.g1.indices.w_first_rad_s && w <= id.g1.indices.w_last_rad_s;
    csv.Add(w).Add(e.frequency_Hz[i]).Add(e.coherence[i]);
    csv.Add(e.response[i].real()).Add(e.response[i].imag());
    csv.Add(20 * std::log10(std::abs(e.response[i]))).Add(measured_deg[i]);
    csv.Add(20 * std::log10(std::abs(p1[i]))).Add(p1_deg[i]);
    csv.Add(20 * std::log10(std::abs(p2[i]))).Add(p2_deg[i]);
    csv.AddInteger(in_band ? 1 : 0).EndRow();
  }
  return csv.Text();
}

// ----------------------------------------------------------------- design ---

PidTuningOptions TuningOptions(const std::string& command, double crossover_rad_s,
                               double reference_order, double horizon_s, double sample_rate_Hz) {
  RequireFinitePositive(command, "horizon_s", horizon_s);
  RequireFinitePositive(command, "sample_rate_Hz", sample_rate_Hz);
  const double samples = horizon_s * sample_rate_Hz;
  if (std::abs(samples - std::round(samples)) > 1e-9 * samples || samples < 2 ||
      samples > kMaxTuningSamples) {
    ThrowOption(command, "horizon_s",
                "a whole number of samples (horizon_s x sample_rate_Hz) in [2, " + FormatDouble(kMaxTuningSamples) + "]",
                FormatDouble(samples));
  }
  if (!std::isfinite(reference_order) || !(reference_order > 0) || reference_order > 2) {
    ThrowOption(command, "reference_order", "in (0, 2]", FormatDouble(reference_order));
  }
  PidTuningOptions options;
  options.reference.crossover_rad_s = crossover_rad_s;
  options.reference.order = reference_order;
  options.horizon_s = horizon_s;
  options.sample_period_s = 1.0 / sample_rate_Hz;
  return options;
}

LinkDesign DesignLink(const DesignSpec& spec, const IpmcLinkParams* own_plant,
                      const std::function<void()>& check_stop) {
  const std::string name = kDesignCommand;
  if (spec.link < 1 || spec.link > 3) {
    ThrowOption(name, "links", "1, 2 or 3", std::to_string(spec.link));
  }
  if (spec.plant != "g1" && spec.plant != "g2") {
    ThrowOption(name, "plant", "g1 or g2", spec.plant);
  }
  RequireFinitePositive(name, "crossover_rad_s", spec.crossover_rad_s);
  RequirePhaseMargin(name, spec.phase_margin_deg);
  LinkDesign result;
  result.link = spec.link;
  result.tuning = TuningOptions(name, spec.crossover_rad_s, spec.reference_order,
                                spec.horizon_s, spec.sample_rate_Hz);
  result.tuning.derivative_filter_s = spec.derivative_filter_s;
  result.params =
      own_plant != nullptr
          ? *own_plant
          : PaperLinkParams(spec.link, spec.plant == "g2" ? IpmcModelKind::kG2 : IpmcModelKind::kG1);
  const IpmcLinkParams params = result.params;
  const FrequencyFunction plant = [params](double w) { return LinkResponseExact(params, w); };
  result.fractional = DesignFractionalLoop(plant, spec.crossover_rad_s, spec.phase_margin_deg);
  const Clock::time_point start = Clock::now();
  PidTuningOptions tuning = result.tuning;
  tuning.check_stop = check_stop;
  const PidLoopDesign pid = DesignPidLoop(params, plant, tuning);
  result.tuning_s = Seconds(start);
  result.paper_cost = pid.paper_cost;
  result.tuned = pid.tuned;
  result.pid_margins = pid.margins;
  return result;
}

// ------------------------------------------------------ the commands ---

namespace {

OptionTable<IdentifyCommand> MakeIdentifyOptions() {
  OptionTable<IdentifyCommand> table(
      kIdentifyCommand, "Frequency response (Welch) and Levy fits of G1 and G2 from bench data");
  OptionInfo data{"data", "", "a CSV file with a header row", "The record"};
  data.positional = true;
  data.required = true;
  table.AddPath(data, [](IdentifyCommand& c) -> std::string& { return c.data_path; });
  OptionInfo input{"input", "", "a column of the record", "Input column [V], e.g. voltage1_V"};
  input.required = true;
  table.Add<std::string>(input, [](IdentifyCommand& c) -> std::string& { return c.input_column; });
  OptionInfo output{"output", "", "a column other than input",
                    "Output column [mm], e.g. relative3_mm"};
  output.required = true;
  table.Add<std::string>(output,
                         [](IdentifyCommand& c) -> std::string& { return c.output_column; });
  table.Add<double>({"sample_rate_Hz", "Hz", "finite and > 0; agrees with a time_s column",
                     "Sample rate of the record"},
                    [](IdentifyCommand& c) -> double& { return c.sample_rate_Hz; });
  table.Add<std::vector<double>>(
      {"band_rad_s", "rad/s", "LOW,HIGH with 0 < LOW < HIGH", "Identification band"},
      [](IdentifyCommand& c) -> std::vector<double>& { return c.band_rad_s; });
  table.Add<double>({"min_coherence", "", "in [0, 1)",
                     "Bins with less coherence do not drive the fits"},
                    [](IdentifyCommand& c) -> double& { return c.min_coherence; });
  table.Add<double>({"min_excitation_dB", "dB", "finite and > 0",
                     "Bins whose input density is further below the band's largest do not "
                     "drive the fits"},
                    [](IdentifyCommand& c) -> double& { return c.min_excitation_dB; });
  OptionInfo plant{"plant", "", "", "The fit written to plant.toml: g1 (eq. 5) or g2 (eq. 6)"};
  plant.choices = {"g1", "g2"};
  table.Add<std::string>(plant, [](IdentifyCommand& c) -> std::string& { return c.plant; });
  OptionInfo links{"link_records", "", "CSV files with the record's columns",
                   "Records of links 2..n, one per link: plant.toml gets one plant per link"};
  table.Add<std::vector<std::string>>(
      links, [](IdentifyCommand& c) -> std::vector<std::string>& { return c.link_records; });
  OptionInfo out{"out", "", "a folder",
                 "Folder for response.csv, identification.json and plant.toml"};
  out.aliases = {"o"};
  table.AddPath(out, [](IdentifyCommand& c) -> std::string& { return c.out; });
  return table;
}

OptionTable<DesignCommand> MakeDesignOptions() {
  OptionTable<DesignCommand> table(
      kDesignCommand, "Fractional integrator (analytic) and PID (Nelder-Mead) for each link");
  table.Add<std::vector<int>>({"links", "", "distinct links 1..3, or 1..n of scenario or plant_file",
                               "Links to design for (default: every link)"},
                              [](DesignCommand& c) -> std::vector<int>& { return c.links; });
  OptionInfo plant{"plant", "", "", "Link model: g1 (eq. 5) or g2 (eq. 6)"};
  plant.choices = {"g1", "g2"};
  table.Add<std::string>(plant, [](DesignCommand& c) -> std::string& { return c.plant; });
  table.Add<double>({"crossover_rad_s", "rad/s", "finite and > 0",
                     "Gain crossover w_c of the fractional integrator, and the crossover of the "
                     "reference model 1/((s/w_c)^gamma + 1) (eq. 9) the PID is tuned against"},
                    [](DesignCommand& c) -> double& { return c.crossover_rad_s; });
  table.Add<double>({"phase_margin_deg", "deg", "in (0, 180)", "Phase margin"},
                    [](DesignCommand& c) -> double& { return c.phase_margin_deg; });
  table.Add<double>({"reference_order", "", "in (0, 2]", "Reference model order gamma (eq. 9)"},
                    [](DesignCommand& c) -> double& { return c.reference_order; });
  table.Add<double>({"horizon_s", "s", "finite and > 0", "Horizon of J (eq. 11)"},
                    [](DesignCommand& c) -> double& { return c.horizon_s; });
  table.Add<double>({"sample_rate_Hz", "Hz", "finite and > 0",
                     "PID rate in the tuning loop: the controllers' 1 kHz (with scenario: its "
                     "controller's, unless given)"},
                    [](DesignCommand& c) -> double& { return c.sample_rate_Hz; });
  table.Add<double>({"derivative_bandwidth_rad_s", "rad/s", "finite and >= 0; 0: none",
                     "PID derivative filter bandwidth w_f: Tf = 1 / w_f in the tuning loop and in "
                     "out (controller.derivative_filter_s)"},
                    [](DesignCommand& c) -> double& { return c.derivative_bandwidth_rad_s; });
  table.Add<double>({"sensor_noise_mm", "mm", "finite and >= 0; 0: none",
                     "RMS noise of the measured deflection, white per sample: the PID derivative "
                     "filter Tf is the smallest that keeps the derivative's noise within "
                     "derivative_noise_V (docs/IDENTIFICATION.md)"},
                    [](DesignCommand& c) -> double& { return c.sensor_noise_mm; });
  table.Add<double>({"derivative_noise_V", "V", "finite and > 0; with sensor_noise_mm",
                     "Bound on the PID derivative's RMS noise voltage"},
                    [](DesignCommand& c) -> double& { return c.derivative_noise_V; });
  OptionInfo scenario{"scenario", "", "a scenario file (TOML)",
                      "Design for each link of this scenario's run: its plants, its link count and "
                      "its controller's sample rate"};
  scenario.default_text = "none: Table 2";
  table.AddPath(scenario, [](DesignCommand& c) -> std::string& { return c.scenario; });
  OptionInfo plant_file{"plant_file", "", "a TOML file of [plant] scenario keys",
                        "Design for the plants these keys give (identify's plant.toml) instead "
                        "of Table 2's"};
  plant_file.default_text = "none: Table 2";
  table.AddPath(plant_file, [](DesignCommand& c) -> std::string& { return c.plant_file; });
  OptionInfo out{"out", "", "a TOML file; links 1..n in order",
                 "Write the tuned PIDs as controller.link_kp, link_ki, link_kd"};
  out.aliases = {"o"};
  table.AddPath(out, [](DesignCommand& c) -> std::string& { return c.out; });
  return table;
}

}  // namespace

const OptionTable<IdentifyCommand>& IdentifyOptions() {
  static const OptionTable<IdentifyCommand> table = MakeIdentifyOptions();
  return table;
}

const OptionTable<DesignCommand>& DesignOptions() {
  static const OptionTable<DesignCommand> table = MakeDesignOptions();
  return table;
}

namespace {

// The columns of the record in the file spec.data_path; a time_s column,
// if present, is checked against the rate.
struct RecordColumns {
  std::vector<double> input, output;
  std::optional<std::vector<double>> time_s;
};
RecordColumns ReadRecordColumns(const IdentifySpec& spec) {
  const CsvTable data = CsvTable::Read(spec.data_path);
  RecordColumns record{data.FiniteNumbers(spec.input_column),
                       data.FiniteNumbers(spec.output_column), std::nullopt};
  if (data.Has(columns::kTime)) record.time_s = data.FiniteNumbers(columns::kTime);
  return record;
}

RecordIdentification IdentifyFile(const IdentifySpec& spec) {
  const RecordColumns record = ReadRecordColumns(spec);
  return IdentifyRecord(spec, record.input, record.output,
                        record.time_s ? &*record.time_s : nullptr);
}

}  // namespace

RecordIdentification RunIdentifyCommand(const IdentifyCommand& command,
                                        const std::vector<double>& input,
                                        const std::vector<double>& output,
                                        const std::vector<double>* time_s) {
  RecordIdentification result = IdentifyRecord(command, input, output, time_s);
  for (const std::string& path : command.link_records) {
    IdentifySpec link = command;
    link.data_path = path;
    result.other_links.push_back(IdentifyFile(link));
  }
  if (!command.out.empty()) {
    const std::string json = IdentificationJson(command, result).dump(2) + "\n";
    EnsureDirectory(command.out);
    const std::filesystem::path dir(command.out);
    WriteFilesTogether({{(dir / "response.csv").string(), ResponseCsv(result.estimate, result.id)},
                        {(dir / "identification.json").string(), json},
                        {(dir / "plant.toml").string(), PlantToml(command, result)}});
  }
  return result;
}

RecordIdentification RunIdentifyCommandOnFile(const IdentifyCommand& command) {
  command.Validate();
  const RecordColumns record = ReadRecordColumns(command);
  return RunIdentifyCommand(command, record.input, record.output,
                            record.time_s ? &*record.time_s : nullptr);
}

namespace {

// The designs with the smallest Tf (to 1 %) whose retuned PIDs keep every
// link's derivative noise (DerivativeNoiseRms_V) within the bound. Tf and
// the tuned Kd move together (a filtered derivative is tuned to a larger
// Kd), so Tf is not the bound's Tf at the ideal derivative's Kd; the noise
// of the retuned loop falls as Tf grows (measured on Table 2's and the
// own strip's plants), and Tf is bracketed by doubling, then bisected in
// log Tf. `ideal` are the designs with the ideal derivative.
std::vector<LinkDesign> DesignForSensorNoise(
    const DesignCommand& command, double sample_rate_Hz,
    const std::function<std::vector<LinkDesign>(double)>& design_links,
    std::vector<LinkDesign> ideal) {
  const double period_s = 1.0 / sample_rate_Hz;
  const auto noise_V = [&](const std::vector<LinkDesign>& designs, double filter_s) {
    double largest = 0;
    for (const LinkDesign& link : designs) {
      largest = std::max(largest, DerivativeNoiseRms_V(link.tuned.gains.kd, filter_s, period_s,
                                                       command.sensor_noise_mm));
    }
    return largest;
  };
  const auto with_noise = [&](std::vector<LinkDesign> designs, double filter_s) {
    for (LinkDesign& link : designs) {
      link.derivative_noise_V = DerivativeNoiseRms_V(link.tuned.gains.kd, filter_s, period_s,
                                                     command.sensor_noise_mm);
    }
    return designs;
  };
  const double bound_V = command.derivative_noise_V;
  if (noise_V(ideal, 0.0) <= bound_V) return with_noise(std::move(ideal), 0.0);
  // A first guess: the bound's Tf at the ideal derivative's Kd.
  double guess_s = 0;
  for (const LinkDesign& link : ideal) {
    guess_s = std::max(guess_s, DerivativeFilterForNoise_s(link.tuned.gains.kd, period_s,
                                                           command.sensor_noise_mm, bound_V));
  }
  double low_s = 0, high_s = guess_s;
  std::vector<LinkDesign> high = design_links(high_s);
  constexpr int kMaxDoublings = 30;
  for (int doubling = 0; noise_V(high, high_s) > bound_V; ++doubling) {
    if (doubling == kMaxDoublings) {
      ThrowOption(kDesignCommand, "derivative_noise_V",
                  "a bound some derivative filter meets (Tf up to " + FormatDouble(high_s) +
                      " s was tried)",
                  FormatDouble(bound_V));
    }
    low_s = high_s;
    high_s *= 2;
    high = design_links(high_s);
  }
  while (high_s - low_s > 1e-2 * high_s) {
    const double mid_s = low_s > 0 ? std::sqrt(low_s * high_s) : high_s / 2;
    std::vector<LinkDesign> mid = design_links(mid_s);
    if (noise_V(mid, mid_s) > bound_V) {
      low_s = mid_s;
    } else {
      high_s = mid_s;
      high = std::move(mid);
    }
  }
  return with_noise(std::move(high), high_s);
}

}  // namespace

std::vector<LinkDesign> RunDesignCommand(const DesignCommand& command, const OptionGiven& given,
                                         const std::function<void()>& check_stop) {
  const auto is_given = [&given](const char* option) { return given && given(option); };
  DesignCommand design = command;
  std::vector<IpmcLinkParams> plants;
  if (!command.scenario.empty()) {
    if (!command.plant_file.empty()) {
      throw FieldError(std::string(kDesignCommand) + ": plant_file does not apply with scenario",
                       "plant_file", "");
    }
    const ScenarioConfig scenario = LoadScenario(command.scenario);
    plants = ScenarioLinkPlants(scenario);
    if (!is_given("sample_rate_Hz")) design.sample_rate_Hz = scenario.controller.sample_rate_Hz;
  } else if (!command.plant_file.empty()) {
    plants = PlantsOfKeyFile(command.plant_file);
  }
  if (!plants.empty() && !is_given("links")) {
    design.links.clear();
    for (std::size_t q = 1; q <= plants.size(); ++q) design.links.push_back(static_cast<int>(q));
  }
  ValidateLinkList(kDesignCommand, design.links,
                   plants.empty() ? 3 : static_cast<int>(plants.size()));
  const double bandwidth = command.derivative_bandwidth_rad_s;
  if (!std::isfinite(bandwidth) || bandwidth < 0) {
    ThrowOption(kDesignCommand, "derivative_bandwidth_rad_s", "finite and >= 0 (0: none)",
                FormatDouble(bandwidth));
  }
  const double noise_mm = command.sensor_noise_mm;
  if (!std::isfinite(noise_mm) || noise_mm < 0) {
    ThrowOption(kDesignCommand, "sensor_noise_mm", "finite and >= 0 (0: none)",
                FormatDouble(noise_mm));
  }
  RequireFinitePositive(kDesignCommand, "derivative_noise_V", command.derivative_noise_V);
  if (noise_mm > 0 && bandwidth > 0) {
    throw FieldError(std::string(kDesignCommand) +
                         ": derivative_bandwidth_rad_s does not apply with sensor_noise_mm",
                     "derivative_bandwidth_rad_s", "");
  }
  if (noise_mm == 0 && is_given("derivative_noise_V")) {
    throw FieldError(std::string(kDesignCommand) +
                         ": derivative_noise_V applies only with sensor_noise_mm",
                     "derivative_noise_V", "");
  }
  if (!command.out.empty()) {
    for (std::size_t i = 0; i < design.links.size(); ++i) {
      if (design.links[i] != static_cast<int>(i) + 1) {
        ThrowOption(kDesignCommand, "out", "links 1..n in order (one gain per link of the run)",
                    "links " + std::to_string(design.links[i]) + " at place " +
                        std::to_string(i + 1));
      }
    }
    RequireWritableParent(command.out);
  }
  const std::function<std::vector<LinkDesign>(double)> design_links = [&](double filter_s) {
    std::vector<LinkDesign> designs;
    for (const int link : design.links) {
      DesignSpec spec = design;
      spec.link = link;
      spec.derivative_filter_s = filter_s;
      designs.push_back(
          DesignLink(spec, plants.empty() ? nullptr : &plants.at(link - 1), check_stop));
    }
    return designs;
  };
  std::vector<LinkDesign> designs = design_links(bandwidth > 0 ? 1.0 / bandwidth : 0.0);
  if (noise_mm > 0) designs = DesignForSensorNoise(command, design.sample_rate_Hz, design_links,
                                                    std::move(designs));
  if (!command.out.empty()) WriteFileAtomically(command.out, GainsToml(design, designs));
  return designs;
}

std::string GainsToml(const DesignCommand& command, const std::vector<LinkDesign>& designs) {
  std::vector<double> kp, ki, kd;
  for (const LinkDesign& design : designs) {
    kp.push_back(design.tuned.gains.kp);
    ki.push_back(design.tuned.gains.ki);
    kd.push_back(design.tuned.gains.kd);
  }
  const std::string plants = !command.scenario.empty()    ? command.scenario
                             : !command.plant_file.empty() ? command.plant_file
                                                           : std::string("Table 2");
  const double filter_s = designs.empty() ? 0.0 : designs.front().tuning.derivative_filter_s;
  return FormatText("# PIDs ipmc-swim design tuned per link for the plants of %s by J of eq. 11\n"
                    "# over %g s against 1/((s/%g)^%g + 1) in a %g Hz loop; a scenario takes\n"
                    "# them with include = [\"gains.toml\"].\n",
                    plants.c_str(), command.horizon_s, command.crossover_rad_s,
                    command.reference_order, command.sample_rate_Hz) +
         "[controller]\nlink_kp = " + *TomlFloats(kp) + "\nlink_ki = " + *TomlFloats(ki) +
         "\nlink_kd = " + *TomlFloats(kd) + "\n" +
         (filter_s > 0 ? "derivative_filter_s = " + FormatShortest(filter_s) + "\n"
                       : std::string()) +
         (command.sensor_noise_mm > 0
              ? FormatText("# derivative_filter_s: the derivative's noise within %g V RMS for a\n"
                           "# sensor noise of %g mm RMS.\n",
                           command.derivative_noise_V, command.sensor_noise_mm)
              : std::string());
}

}  // namespace ipmc
