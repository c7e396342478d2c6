#include "sim/cli/identify_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/io/files.h"
#include "sim/core/data_paths.h"
#include "sim/io/numbers.h"
#include "controllers/linear/frequency_response.h"
#include "controllers/reference_model.h"
#include "plugin/actuators/ipmc_actuators.h"
#include "plugin/actuators/ipmc_link_model.h"
#include "sim/runs/bench_run.h"
#include "sim/identify/controller_design.h"
#include "sim/identify/identify_run.h"
#include "sim/identify/levy.h"
#include "sim/runs/output.h"
#include "sim/core/simulation.h"
#include "sim/identify/welch.h"

namespace ipmc {
namespace {

using Complex = std::complex<double>;
using Clock = std::chrono::steady_clock;

constexpr char kIdentifyCommand[] = "identify";
constexpr char kDesignCommand[] = "design";
constexpr char kPipelineCommand[] = "pipeline";

constexpr char kDriveEach[] = "each";
constexpr char kDriveFirst[] = "first";
constexpr char kTimeColumn[] = "time_s";

// The bench records at the data-acquisition board's rate.
constexpr double kBenchSampleRate_Hz = 1000.0;
// Paper's eq. 12 and eq. 14, for comparison.
constexpr PidGains kPaperPid{8.12, 53.36, 0.61};
constexpr double kPaperFractionalGain = 15.62;
constexpr double kPaperFractionalOrder = 0.62;
// Bounds on the options that size the work.
constexpr double kMaxDuration_s = 1e4;
constexpr int kMaxRepeats = 100;
constexpr double kMaxAmplitude_V = 100.0;  // as BenchSignal

double Seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string Format(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string Format(const char* format, ...) {
  va_list args;
  va_start(args, format);
  va_list copy;
  va_copy(copy, args);
  const int length = std::vsnprintf(nullptr, 0, format, copy);
  va_end(copy);
  std::string text(length > 0 ? length : 0, '\0');
  if (length > 0) std::vsnprintf(text.data(), text.size() + 1, format, args);
  va_end(args);
  return text;
}

[[noreturn]] void ThrowOption(const std::string& command, const std::string& option,
                              const std::string& requirement, const std::string& got) {
  throw std::invalid_argument(command + ": " + option + " must be " + requirement + ", got " +
                              got);
}

void RequireFinitePositive(const std::string& command, const std::string& option, double value) {
  if (!std::isfinite(value) || !(value > 0)) {
    ThrowOption(command, option, "finite and > 0", FormatDouble(value));
  }
}

void RequirePhaseMargin(const std::string& command, double value) {
  if (!std::isfinite(value) || !(value > 0) || !(value < 180)) {
    ThrowOption(command, "--phase-margin-deg", "in (0, 180)", FormatDouble(value));
  }
}

// ------------------------------------------------------------------ CSV ---

std::string Trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  const auto last = text.find_last_not_of(" \t\r");
  return text.substr(first, last - first + 1);
}

std::vector<std::string> SplitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream stream(line);
  while (std::getline(stream, field, ',')) fields.push_back(Trim(field));
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

struct CsvData {
  std::vector<std::vector<double>> columns;  // as requested
  std::optional<std::vector<double>> time_s;
};

// Reads the named columns (and time_s if present) of a CSV file with a
// header row. Throws std::invalid_argument naming the file, line and
// column on any malformed or non-finite cell.
CsvData ReadCsvColumns(const std::string& path, const std::vector<std::string>& names) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(path + ": cannot open file");
  std::string line;
  if (!std::getline(in, line)) throw std::invalid_argument(path + ": empty file (no header row)");
  const std::vector<std::string> header = SplitFields(line);
  const auto find = [&](const std::string& name) -> int {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  };
  std::vector<int> index;
  for (const std::string& name : names) {
    const int i = find(name);
    if (i < 0) {
      std::string available;
      for (const std::string& h : header) available += (available.empty() ? "" : ", ") + h;
      throw std::invalid_argument(path + ": no column '" + name + "' (columns: " + available +
                                  ")");
    }
    index.push_back(i);
  }
  const int time_index = find(kTimeColumn);

  CsvData data;
  data.columns.resize(names.size());
  if (time_index >= 0) data.time_s.emplace();
  const auto parse = [&](const std::string& field, long line_number,
                         const std::string& column) {
    const char* begin = field.c_str();
    char* end = nullptr;
    const double value = std::strtod(begin, &end);
    const std::string where = path + ":" + std::to_string(line_number) + ": column " + column;
    if (field.empty() || end != begin + field.size()) {
      throw std::invalid_argument(where + ": '" + field + "' is not a number");
    }
    if (!std::isfinite(value)) {
      throw std::invalid_argument(where + ": value is not finite (" + field + ")");
    }
    return value;
  };
  long line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (Trim(line).empty()) continue;
    const std::vector<std::string> fields = SplitFields(line);
    if (fields.size() != header.size()) {
      throw std::invalid_argument(path + ":" + std::to_string(line_number) + ": expected " +
                                  std::to_string(header.size()) + " fields (as the header), got " +
                                  std::to_string(fields.size()));
    }
    for (std::size_t c = 0; c < names.size(); ++c) {
      data.columns[c].push_back(parse(fields[index[c]], line_number, names[c]));
    }
    if (time_index >= 0) {
      data.time_s->push_back(parse(fields[time_index], line_number, kTimeColumn));
    }
  }
  return data;
}

// --------------------------------------------------------- formatting ---

std::string StabilityText(const LinkModelFit& fit) { return fit.stable ? "stable" : "UNSTABLE"; }

std::string DescribeG1(const LinkModelFit& fit) {
  const IpmcLinkParams& p = fit.params;
  std::string text = Format("G1 = a0 / (b2 s^2 + b1 s + 1): a0 = %.5g mm/V, b1 = %.5g s, "
                            "b2 = %.5g s^2 (%s",
                            p.a0_mm_per_V, p.b1, p.b2_s2, StabilityText(fit).c_str());
  if (p.b2_s2 > 0 && p.b1 > 0) {
    text += Format("; zeta = %.4f, w_n = %.4g rad/s", p.b1 / (2 * std::sqrt(p.b2_s2)),
                   1 / std::sqrt(p.b2_s2));
  }
  return text + ")";
}

std::string DescribeG2(const LinkModelFit& fit, const LinkIdentification& id) {
  const IpmcLinkParams& p = fit.params;
  return Format("G2 = a0 / (b1 s^alpha + 1): alpha = %.2f, a0 = %.5g mm/V, b1 = %.5g s^alpha "
                "(%s; %d of %d orders stable)",
                p.alpha, p.a0_mm_per_V, p.b1, StabilityText(fit).c_str(), id.g2_orders_stable,
                id.g2_orders_tried);
}

std::string WelchDescription(const FrequencyResponseEstimate& e) {
  const double resolution_Hz = e.sample_rate_Hz / e.section_samples;
  return Format("Welch: %d record%s x %d sections of %d samples (%.4g s), %d-sample step "
                "(50 %% overlap), Hamming window; resolution %.4g Hz (%.4g rad/s)",
                e.records, e.records == 1 ? "" : "s", e.sections_per_record, e.section_samples,
                e.section_samples / e.sample_rate_Hz, e.section_step, resolution_Hz,
                kTwoPi * resolution_Hz);
}

double MeanCoherenceInBand(const FrequencyResponseEstimate& e, const FitIndices& indices) {
  double sum = 0;
  int count = 0;
  for (std::size_t i = 0; i < e.w_rad_s.size(); ++i) {
    if (e.w_rad_s[i] >= indices.w_first_rad_s && e.w_rad_s[i] <= indices.w_last_rad_s) {
      sum += e.coherence[i];
      ++count;
    }
  }
  return count > 0 ? sum / count : 0.0;
}

void PrintIndicesTable(const LinkIdentification& id) {
  std::printf("Table 3 indices on P = s^-0.5 G (complex response, band points):\n");
  std::printf("%-5s %12s %12s %12s %12s %9s\n", "model", "J", "MSE", "MAD", "MD", "R^2");
  const std::pair<const char*, const LinkModelFit*> rows[] = {{"P1", &id.g1}, {"P2", &id.g2}};
  for (const auto& [name, fit] : rows) {
    const FitIndices& i = fit->indices;
    std::printf("%-5s %12.5g %12.5g %12.5g %12.5g %9.5f\n", name, i.levy_cost, i.mse, i.mad,
                i.max_deviation, i.r_squared);
  }
}

// Raises the band's low end to the first Welch bin if the record is too
// short for it; returns a note saying so (empty if not needed).
std::string FitBandToData(LevyOptions& levy, const FrequencyResponseEstimate& e) {
  if (levy.w_low_rad_s >= e.w_rad_s.front()) return "";
  const std::string note =
      Format("the band's low end %.4g rad/s is below the first Welch bin; the fit starts at "
             "%.4g rad/s",
             levy.w_low_rad_s, e.w_rad_s.front());
  levy.w_low_rad_s = e.w_rad_s.front();
  return note;
}

// ------------------------------------------------------------ identify ---

int RunIdentify(const IdentifyArgs::Identify& args) {
  args.Validate();
  const CsvData data = ReadCsvColumns(args.data_path, {args.input_column, args.output_column});
  const std::vector<double>& input = data.columns[0];
  const RecordIdentification result = IdentifyRecord(
      args, input, data.columns[1], data.time_s ? &*data.time_s : nullptr);
  const LevyOptions& levy = result.levy;
  const FrequencyResponseEstimate& estimate = result.estimate;
  const LinkIdentification& id = result.id;

  std::printf("%s: input %s, output %s, %zu samples at %g Hz (%.6g s)\n", args.data_path.c_str(),
              args.input_column.c_str(), args.output_column.c_str(), input.size(),
              args.sample_rate_hz, input.size() / args.sample_rate_hz);
  std::printf("%s\n", WelchDescription(estimate).c_str());
  std::printf("Levy over [%g, %g] rad/s: %d points from %.4g to %.4g rad/s, mean coherence %.4f; "
              "s^-0.5 removed\n",
              levy.w_low_rad_s, levy.w_high_rad_s, id.g1.indices.points,
              id.g1.indices.w_first_rad_s, id.g1.indices.w_last_rad_s,
              MeanCoherenceInBand(estimate, id.g1.indices));
  std::printf("P1 = s^-0.5 G1, %s\n", DescribeG1(id.g1).c_str());
  std::printf("P2 = s^-0.5 G2, %s\n", DescribeG2(id.g2, id).c_str());
  PrintIndicesTable(id);

  if (!args.out_dir.empty()) {
    const nlohmann::json json = IdentificationJson(args, result);
    EnsureDirectory(args.out_dir);
    const std::filesystem::path dir(args.out_dir);
    WriteFileAtomically((dir / "response.csv").string(), ResponseCsv(estimate, id));
    WriteFileAtomically((dir / "identification.json").string(), json.dump(2) + "\n");
    std::printf("wrote %s and %s\n", (dir / "response.csv").string().c_str(),
                (dir / "identification.json").string().c_str());
  }
  return 0;
}

// -------------------------------------------------------------- design ---

std::string MarginsText(const StabilityMargins& m) {
  std::string text = m.gain_crossover_rad_s
                         ? Format("crossover %.4f rad/s, phase margin %.2f deg",
                                  *m.gain_crossover_rad_s, *m.phase_margin_deg)
                         : std::string("no gain crossover");
  text += m.gain_margin_db ? Format(", gain margin %.2f dB at %.4g rad/s", *m.gain_margin_db,
                                    *m.phase_crossover_rad_s)
                           : std::string(", no finite gain margin");
  return text;
}

std::string PidText(const PidGains& g) {
  return Format("C(s) = %.4g + %.4g/s + %.4g s", g.kp, g.ki, g.kd);
}

int RunDesign(const IdentifyArgs::Design& args) {
  const LinkDesign result = DesignLink(args);
  const FractionalResult& fractional = result.fractional;
  std::printf("plant: link %d, P = s^-0.5 %s (Table 2%s)\n", args.link,
              args.plant == "g2" ? "G2" : "G1",
              args.link == 3 && args.plant == "g1" ? ", eq. 7" : "");
  const FractionalIntegratorDesign& d = fractional.design;
  std::printf("fractional integrator for crossover %g rad/s, phase margin %g deg:\n",
              args.crossover_rad_s, args.phase_margin_deg);
  std::printf("  |P(j w_c)| = %.6g mm/V, arg P(j w_c) = %.4f deg\n", d.plant_magnitude,
              d.plant_phase_deg);
  std::printf("  C_I(s) = %.4f / s^%.4f  (lambda = (arg P + 180 - PM) / 90, K = w_c^lambda / "
              "|P|; paper eq. 14: %.2f / s^%.2f)\n",
              d.gain, d.order, kPaperFractionalGain, kPaperFractionalOrder);
  std::printf("  open loop (exact): %s\n", MarginsText(fractional.margins).c_str());

  const PidTuningResult& tuned = result.tuned;
  const double paper_cost = result.paper_cost;
  std::printf("PID tuned by Nelder-Mead against 1/((s/%g)^%g + 1), J of eq. 11 over %g s, loop "
              "sampled at %g Hz (linear, no clamp):\n",
              args.crossover_rad_s, args.reference_order, args.horizon_s, args.sample_rate_hz);
  std::printf("  %-34s %-34s %10s %10s %6s\n", "start", "result", "J_start", "J", "evals");
  for (const PidTuningRun& run : tuned.runs) {
    std::printf("  %-34s %-34s %10.6f %10.6f %6d%s\n", PidText(run.start).c_str(),
                PidText(run.gains).c_str(), run.start_cost, run.cost, run.evaluations,
                run.converged ? "" : " (not converged)");
  }
  std::printf("  paper (eq. 12): %s, J = %.6f\n", PidText(kPaperPid).c_str(), paper_cost);
  std::printf("  tuned:          %s, J = %.6f (%.1f %% of the paper's)\n",
              PidText(tuned.gains).c_str(), tuned.cost, 100 * tuned.cost / paper_cost);
  std::printf("  tuned open loop (exact plant, continuous PID): %s\n",
              MarginsText(result.pid_margins).c_str());
  std::printf("  tuning time %.2f s\n", result.tuning_s);
  return 0;
}

// ------------------------------------------------------------ pipeline ---

struct PipelineLink {
  int link = 0;                         // 1-based
  std::string measured;                 // what was measured
  FrequencyResponseEstimate estimate;
  LevyOptions levy;
  std::string band_note;
  LinkIdentification id;
  std::optional<IpmcLinkParams> given;  // the simulator's parameters
  double identify_s = 0;                // Welch + Levy time
};

std::string Milli(double value) { return Format("%.4g", 1e3 * value); }

std::string Deviation(double identified, double given) {
  return Format("%+.1f %%", 100 * (identified / given - 1));
}

int RunPipeline(const IdentifyArgs::Pipeline& args) {
  const std::string name = kPipelineCommand;
  if (args.drive != kDriveEach && args.drive != kDriveFirst) {
    ThrowOption(name, "--drive", "each or first", args.drive);
  }
  RequireFinitePositive(name, "--duration-s", args.duration_s);
  if (args.duration_s > kMaxDuration_s) {
    ThrowOption(name, "--duration-s", "at most " + FormatDouble(kMaxDuration_s),
                FormatDouble(args.duration_s));
  }
  if (args.repeats < 1 || args.repeats > kMaxRepeats) {
    ThrowOption(name, "--repeats", "in [1, " + std::to_string(kMaxRepeats) + "]",
                std::to_string(args.repeats));
  }
  if (!std::isfinite(args.noise_mm) || args.noise_mm < 0) {
    ThrowOption(name, "--noise-mm", "finite and >= 0", FormatDouble(args.noise_mm));
  }
  if (!std::isfinite(args.amplitude_v) || args.amplitude_v == 0 ||
      std::abs(args.amplitude_v) > kMaxAmplitude_V) {
    ThrowOption(name, "--amplitude-v", "finite, nonzero and within +-" +
                FormatDouble(kMaxAmplitude_V), FormatDouble(args.amplitude_v));
  }
  RequireFinitePositive(name, "--f0-hz", args.f0_hz);
  if (!std::isfinite(args.f1_hz) || !(args.f1_hz > args.f0_hz) ||
      !(args.f1_hz < 0.5 * kBenchSampleRate_Hz)) {
    ThrowOption(name, "--f1-hz",
                Format("in (%g, %g) (above --f0-hz, below half the %g Hz sample rate)",
                       args.f0_hz, 0.5 * kBenchSampleRate_Hz, kBenchSampleRate_Hz),
                FormatDouble(args.f1_hz));
  }
  RequireFinitePositive(name, "--crossover-rad-s", args.crossover_rad_s);
  RequirePhaseMargin(name, args.phase_margin_deg);
  const LevyOptions band = BandOptions(name, args.band_rad_s);
  const PidTuningOptions tuning =
      TuningOptions(name, args.crossover_rad_s, ReferenceModel::Config{}.order, args.horizon_s,
                    1e4);

  BenchSignal signal;
  signal.kind = BenchSignal::Kind::kChirp;
  signal.amplitude_V = args.amplitude_v;
  signal.start_Hz = args.f0_hz;
  signal.end_Hz = args.f1_hz;
  signal.duration_s = args.duration_s;
  signal.sample_rate_Hz = kBenchSampleRate_Hz;
  signal.Validate();

  const std::string model_path = args.model_path.empty()
                                     ? ModelsDir() + "/flagellum3_clamped.xml"
                                     : args.model_path;
  const bool drive_each = args.drive == kDriveEach;
  // One simulation per run, made (and attached) before the threads start.
  std::vector<std::unique_ptr<Simulation>> sims;
  sims.push_back(std::make_unique<Simulation>(LoadModelFile(model_path), model_path));
  const std::optional<IpmcActuatorsConfig> config =
      IpmcActuatorsConfig::FromModel(sims.front()->model());
  if (!config) throw std::invalid_argument(name + ": " + model_path + " has no IPMC actuators");
  const int links = static_cast<int>(config->links.size());
  if (drive_each && config->actuation == Actuation::kSingle && links > 1) {
    throw std::invalid_argument(name + ": --drive each needs distributed actuation, but " +
                                model_path + " has ipmc_actuation single");
  }
  const int runs = drive_each ? links : 1;
  for (int r = 1; r < runs; ++r) {
    sims.push_back(std::make_unique<Simulation>(LoadModelFile(model_path), model_path));
  }

  const Clock::time_point bench_start = Clock::now();
  std::vector<BenchRecord> records(runs);
  std::vector<std::exception_ptr> errors(runs);
  std::vector<std::thread> threads;
  for (int r = 0; r < runs; ++r) {
    threads.emplace_back([&, r]() {
      try {
        BenchSignal run_signal = signal;
        run_signal.driven_links = {r + 1};
        records[r] = RunBench(*sims[r], run_signal);
      } catch (...) {
        errors[r] = std::current_exception();
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (const std::exception_ptr& error : errors) {
    if (error) std::rethrow_exception(error);
  }
  const double bench_s = Seconds(bench_start);

  std::vector<PipelineLink> results;
  for (int q = 0; q < links; ++q) {
    const Clock::time_point start = Clock::now();
    const BenchRecord& record = records[drive_each ? q : 0];
    const int driven = drive_each ? q : 0;
    PipelineLink result;
    result.link = q + 1;
    result.measured = drive_each ? Format("relative%d_mm (link %d driven)", q + 1, q + 1)
                                 : Format("tip%d_lateral_mm (link 1 driven)", q + 1);
    const std::vector<double>& clean =
        drive_each ? record.relative_mm[q] : record.tip_lateral_mm[q];
    std::vector<std::vector<double>> inputs(args.repeats, record.voltage_V[driven]);
    std::vector<std::vector<double>> outputs(args.repeats, clean);
    if (args.noise_mm > 0) {
      for (int r = 0; r < args.repeats; ++r) {
        std::mt19937_64 rng(args.seed + 1000003ULL * static_cast<unsigned long long>(q) + r);
        std::normal_distribution<double> noise(0.0, args.noise_mm);
        for (double& y : outputs[r]) y += noise(rng);
      }
    }
    WelchOptions welch;
    welch.sample_rate_Hz = kBenchSampleRate_Hz;
    result.estimate = EstimateFrequencyResponse(inputs, outputs, welch);
    result.levy = band;
    result.band_note = FitBandToData(result.levy, result.estimate);
    result.id = IdentifyLinkModels(result.estimate, result.levy);
    if (drive_each || q == 0) result.given = config->links[q];
    result.identify_s = Seconds(start);
    results.push_back(std::move(result));
  }

  // Designs on the identified model of link 3 (or the last link).
  const PipelineLink& design_link = results[std::min(3, links) - 1];
  std::ostringstream design;
  double tuning_s = 0;
  if (!design_link.id.g1.stable) {
    design << "The identified G1 of link " << design_link.link
           << " is unstable: no controller designed.\n";
  } else {
    const IpmcLinkParams identified = design_link.id.g1.params;
    const FrequencyFunction plant = [identified](double w) {
      return FittedResponse(identified, w);
    };
    design << Format("Plant: the identified P%d = s^-0.5 G1 of link %d. Specifications: "
                     "crossover %g rad/s, phase margin %g deg; reference model "
                     "1/((s/%g)^%g + 1).\n\n",
                     design_link.link, design_link.link, args.crossover_rad_s,
                     args.phase_margin_deg, args.crossover_rad_s, tuning.reference.order);
    design << "| controller | on | gains | open loop |\n|---|---|---|---|\n";
    const FractionalResult fractional =
        DesignFractional(plant, args.crossover_rad_s, args.phase_margin_deg);
    design << Format("| fractional integrator (analytic) | identified | K = %.4f, lambda = %.4f "
                     "| %s |\n",
                     fractional.design.gain, fractional.design.order,
                     MarginsText(fractional.margins).c_str());
    if (design_link.given) {
      const IpmcLinkParams given = *design_link.given;
      const FractionalResult reference = DesignFractional(
          [given](double w) { return LinkResponseExact(given, w); }, args.crossover_rad_s,
          args.phase_margin_deg);
      design << Format("| fractional integrator (analytic) | simulator's model | K = %.4f, "
                       "lambda = %.4f | %s |\n",
                       reference.design.gain, reference.design.order,
                       MarginsText(reference.margins).c_str());
    }
    design << Format("| fractional integrator, paper eq. 14 | eq. 7 | K = %.2f, lambda = %.2f "
                     "| - |\n",
                     kPaperFractionalGain, kPaperFractionalOrder);
    const Clock::time_point start = Clock::now();
    const StateSpace accurate = AccurateLinkPlant(identified);
    const PidStepCost cost(accurate, tuning);
    const double paper_cost = cost(kPaperPid);
    const PidTuningResult tuned = TunePid(accurate, tuning);
    tuning_s = Seconds(start);
    const PidGains g = tuned.gains;
    const StabilityMargins pid_margins = ComputeMargins([&](double w) {
      return (g.kp + g.ki / Complex(0, w) + g.kd * Complex(0, w)) * plant(w);
    });
    design << Format("| PID (Nelder-Mead, %zu starts) | identified | Kp = %.4g, Ki = %.4g, "
                     "Kd = %.4g | %s |\n",
                     tuned.runs.size(), g.kp, g.ki, g.kd, MarginsText(pid_margins).c_str());
    design << Format("| PID, paper eq. 12 | eq. 7 | Kp = %.2f, Ki = %.2f, Kd = %.2f | - |\n\n",
                     kPaperPid.kp, kPaperPid.ki, kPaperPid.kd);
    design << Format("J of eq. 11 over %g s on the identified plant (unit step, loop sampled "
                     "at 10 kHz, linear): %.6f at the paper's gains, %.6f tuned (%.1f %%).\n",
                     args.horizon_s, paper_cost, tuned.cost, 100 * tuned.cost / paper_cost);
  }

  // The report.
  const FrequencyResponseEstimate& first = results.front().estimate;
  std::ostringstream report;
  report << "# Identification of the simulated flagellum\n\n";
  report << Format("Model `%s`, %d IPMC links. Bench experiment (paper section 4.1): "
                   "%g V chirp from %g to %g Hz over %g s, recorded at %g Hz; ",
                   model_path.c_str(), links, args.amplitude_v, args.f0_hz, args.f1_hz,
                   args.duration_s, kBenchSampleRate_Hz);
  report << (drive_each ? "each link driven in turn, its relative tip deflection "
                          "L_q sin(theta_q) measured.\n"
                        : "link 1 driven, the lateral position of every tip measured (the "
                          "paper's experiment).\n");
  report << Format("Repeats: %d, measurement noise %g mm (the simulator is deterministic: "
                   "repeats differ only by the noise).\n\n",
                   args.repeats, args.noise_mm);
  report << WelchDescription(first)
         << Format(". Levy's method over [%g, %g] rad/s after removing s^-0.5; G2's alpha swept "
                   "over 1.01..1.99, the stable fit of least J kept.\n",
                   band.w_low_rad_s, band.w_high_rad_s);
  const bool same_notes =
      std::all_of(results.begin(), results.end(),
                  [&](const PipelineLink& r) { return r.band_note == results.front().band_note; });
  if (same_notes && !results.front().band_note.empty()) {
    report << "\nAll links: " << results.front().band_note << ".\n";
  } else if (!same_notes) {
    for (const PipelineLink& r : results) {
      if (!r.band_note.empty()) report << "\nLink " << r.link << ": " << r.band_note << ".\n";
    }
  }

  report << "\n## Identified models (as Table 2)\n\n";
  report << "P = s^-0.5 G; a0 [1e-3 mm/V], b2 [1e-3 s^2], b1 [1e-3 s or s^alpha].\n\n";
  report << "| link | measured | model | alpha | a0 | b2 | b1 | stable |\n";
  report << "|---|---|---|---|---|---|---|---|\n";
  for (const PipelineLink& r : results) {
    const IpmcLinkParams& g1 = r.id.g1.params;
    const IpmcLinkParams& g2 = r.id.g2.params;
    report << Format("| %d | %s | G1 | - | %s | %s | %s | %s |\n", r.link, r.measured.c_str(),
                     Milli(g1.a0_mm_per_V).c_str(), Milli(g1.b2_s2).c_str(),
                     Milli(g1.b1).c_str(), r.id.g1.stable ? "yes" : "no");
    if (r.given && r.given->kind == IpmcModelKind::kG1) {
      const IpmcLinkParams& s = *r.given;
      report << Format("| %d | | G1, simulator's | - | %s | %s | %s | |\n", r.link,
                       Milli(s.a0_mm_per_V).c_str(), Milli(s.b2_s2).c_str(), Milli(s.b1).c_str());
      report << Format("| %d | | deviation | | %s | %s | %s | |\n", r.link,
                       Deviation(g1.a0_mm_per_V, s.a0_mm_per_V).c_str(),
                       Deviation(g1.b2_s2, s.b2_s2).c_str(), Deviation(g1.b1, s.b1).c_str());
    }
    report << Format("| %d | | G2 | %.2f | %s | - | %s | %s |\n", r.link, g2.alpha,
                     Milli(g2.a0_mm_per_V).c_str(), Milli(g2.b1).c_str(),
                     r.id.g2.stable ? "yes" : "no");
    if (r.given && r.given->kind == IpmcModelKind::kG2) {
      const IpmcLinkParams& s = *r.given;
      report << Format("| %d | | G2, simulator's | %.2f | %s | - | %s | |\n", r.link, s.alpha,
                       Milli(s.a0_mm_per_V).c_str(), Milli(s.b1).c_str());
    }
  }
  if (!drive_each && links > 1) {
    // Section 4.3: K_q = a0_q / a0_(q-1), each tip against the one before.
    report << "\nGains of each tip against the one before (a0 of G1, as section 4.3):";
    for (int q = 1; q < links; ++q) {
      report << Format(" K%d = %.3f", q + 1,
                       results[q].id.g1.params.a0_mm_per_V /
                           results[q - 1].id.g1.params.a0_mm_per_V);
    }
    report << ".\n";
  }

  report << "\n## Fit indices (as Table 3)\n\n";
  report << "On the complex P over the band points: J = sum |G D - N|^2 (Levy, [(mm/V)^2]), "
            "MSE = mean |e|^2, MAD = mean |e|, MD = max |e| [mm/V], "
            "R^2 = 1 - sum |e|^2 / sum |P - mean P|^2, e = P_measured - P_model.\n\n";
  report << "| link | model | points | J | MSE | MAD | MD | R^2 |\n";
  report << "|---|---|---|---|---|---|---|---|\n";
  for (const PipelineLink& r : results) {
    const std::pair<const char*, const LinkModelFit*> rows[] = {{"P1", &r.id.g1},
                                                                {"P2", &r.id.g2}};
    for (const auto& [label, fit] : rows) {
      const FitIndices& i = fit->indices;
      report << Format("| %d | %s | %d | %.4g | %.4g | %.4g | %.4g | %.4f |\n", r.link, label,
                       i.points, i.levy_cost, i.mse, i.mad, i.max_deviation, i.r_squared);
    }
  }

  report << "\n## Controllers for link " << design_link.link << " (section 5.2)\n\n";
  report << design.str();

  report << "\n## Timing\n\n";
  report << Format("Bench simulation: %.2f s wall for %d run%s of %g s%s. "
                   "Welch and Levy (with the alpha sweep) per link:",
                   bench_s, runs, runs == 1 ? "" : "s", args.duration_s,
                   runs == 1 ? "" : " in parallel threads");
  for (const PipelineLink& r : results) report << Format(" %.3f s", r.identify_s);
  report << Format(". PID tuning: %.2f s.\n", tuning_s);

  const std::string text = report.str();
  std::printf("%s", text.c_str());
  if (!args.out_dir.empty()) {
    EnsureDirectory(args.out_dir);
    const std::filesystem::path dir(args.out_dir);
    for (const PipelineLink& r : results) {
      WriteFileAtomically((dir / ("response_link" + std::to_string(r.link) + ".csv")).string(),
                          ResponseCsv(r.estimate, r.id));
    }
    WriteFileAtomically((dir / "report.md").string(), text);
  }
  return 0;
}

}  // namespace

void AddIdentifyCommands(CLI::App& app, IdentifyArgs& args) {
  IdentifyArgs::Identify& i = args.identify;
  CLI::App* identify = app.add_subcommand(
      kIdentifyCommand, "Frequency response (Welch) and Levy fits of G1 and G2 from bench data");
  identify->add_option("data", i.data_path, "CSV file with a header row")->required();
  identify->add_option("--input", i.input_column, "Input column, e.g. voltage1_V")->required();
  identify->add_option("--output", i.output_column, "Output column, e.g. relative3_mm")
      ->required();
  identify->add_option("--sample-rate-hz", i.sample_rate_hz, "Sample rate [Hz]")
      ->capture_default_str();
  identify->add_option("--band-rad-s", i.band_rad_s, "Identification band LOW,HIGH [rad/s]")
      ->delimiter(',')->capture_default_str();
  identify->add_option("--out", i.out_dir, "Directory for response.csv and identification.json");

  IdentifyArgs::Design& d = args.design;
  CLI::App* design = app.add_subcommand(
      kDesignCommand, "Fractional integrator (analytic) and PID (Nelder-Mead) for one link");
  design->add_option("--link", d.link, "Link 1..3 (Table 2)")->capture_default_str();
  design->add_option("--plant", d.plant, "g1 (eq. 5) | g2 (eq. 6)")
      ->check(CLI::IsMember({"g1", "g2"}))->capture_default_str();
  design->add_option("--crossover-rad-s", d.crossover_rad_s, "Gain crossover w_c [rad/s]")
      ->capture_default_str();
  design->add_option("--phase-margin-deg", d.phase_margin_deg, "Phase margin [deg]")
      ->capture_default_str();
  design->add_option("--reference-order", d.reference_order,
                     "Reference model order gamma, in (0, 2]")->capture_default_str();
  design->add_option("--horizon-s", d.horizon_s, "Horizon of J (eq. 11) [s]")
      ->capture_default_str();
  design->add_option("--sample-rate-hz", d.sample_rate_hz, "PID rate in the tuning loop [Hz]")
      ->capture_default_str();

  IdentifyArgs::Pipeline& p = args.pipeline;
  CLI::App* pipeline = app.add_subcommand(
      kPipelineCommand,
      "Bench chirp on the simulated clamped flagellum, identification and design, as a report");
  pipeline->add_option("--model", p.model_path,
                       "MJCF model with IPMC actuators (default models/flagellum3_clamped.xml)");
  pipeline->add_option("--drive", p.drive,
                       "each: each link in turn, its relative deflection | first: link 1, every "
                       "tip (the paper)")
      ->check(CLI::IsMember({kDriveEach, kDriveFirst}))->capture_default_str();
  pipeline->add_option("--duration-s", p.duration_s, "Chirp duration [s]")->capture_default_str();
  pipeline->add_option("--amplitude-v", p.amplitude_v, "Chirp amplitude [V]")
      ->capture_default_str();
  pipeline->add_option("--f0-hz", p.f0_hz, "Chirp start frequency [Hz]")->capture_default_str();
  pipeline->add_option("--f1-hz", p.f1_hz, "Chirp end frequency [Hz]")->capture_default_str();
  pipeline->add_option("--repeats", p.repeats, "Records per link (differ by the noise only)")
      ->capture_default_str();
  pipeline->add_option("--noise-mm", p.noise_mm, "Measurement noise standard deviation [mm]")
      ->capture_default_str();
  pipeline->add_option("--seed", p.seed, "Noise seed")->capture_default_str();
  pipeline->add_option("--band-rad-s", p.band_rad_s, "Identification band LOW,HIGH [rad/s]")
      ->delimiter(',')->capture_default_str();
  pipeline->add_option("--crossover-rad-s", p.crossover_rad_s, "Design crossover w_c [rad/s]")
      ->capture_default_str();
  pipeline->add_option("--phase-margin-deg", p.phase_margin_deg, "Design phase margin [deg]")
      ->capture_default_str();
  pipeline->add_option("--horizon-s", p.horizon_s, "Horizon of J (eq. 11) [s]")
      ->capture_default_str();
  pipeline->add_option("--out", p.out_dir, "Directory for report.md and response_link<q>.csv");
}

int RunIdentifyCommand(const CLI::App& app, const IdentifyArgs& args) {
  if (app.got_subcommand(kIdentifyCommand)) return RunIdentify(args.identify);
  if (app.got_subcommand(kDesignCommand)) return RunDesign(args.design);
  if (app.got_subcommand(kPipelineCommand)) return RunPipeline(args.pipeline);
  return -1;
}

}  // namespace ipmc
