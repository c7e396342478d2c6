#include "sim/cli/identify_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "controllers/fractional_integrator.h"
#include "controllers/linear/frequency_response.h"
#include "controllers/reference_model.h"
#include "plugin/actuators/ipmc_actuators.h"
#include "plugin/actuators/ipmc_link_model.h"
#include "sim/core/data_paths.h"
#include "sim/core/fan_out.h"
#include "sim/core/simulation.h"
#include "sim/cli/command.h"
#include "sim/identify/bench_identification.h"
#include "sim/identify/controller_design.h"
#include "sim/identify/identify_run.h"
#include "sim/identify/levy.h"
#include "sim/identify/loop_analysis.h"
#include "sim/identify/welch.h"
#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "plugin/base/error.h"
#include "sim/io/files.h"
#include "plugin/base/numbers.h"
#include "sim/runs/bench_run.h"

namespace ipmc {
namespace {

using Complex = std::complex<double>;
using Clock = std::chrono::steady_clock;

constexpr char kIdentifyCommand[] = "identify";
constexpr char kDesignCommand[] = "design";
constexpr char kPipelineCommand[] = "pipeline";

constexpr char kDriveEach[] = "each";
constexpr char kDriveFirst[] = "first";

// The bench records at the data-acquisition board's rate.
constexpr double kBenchSampleRate_Hz = 1000.0;
// Paper's eq. 12 and eq. 14 (the controllers' defaults), for comparison.
const PidGains kPaperPid{};
const FractionalIntegrator::Config kPaperFractional{};
// The PID's rate in the pipeline's tuning loop.
constexpr double kPipelinePidRate_Hz = 1e4;
// Bounds on the options that size the work.
constexpr double kMaxDuration_s = 1e4;
constexpr int kMaxRepeats = 100;
constexpr double kMaxAmplitude_V = 100.0;  // as BenchSignal

double Seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string StabilityText(const LinkModelFit& fit) { return fit.stable ? "stable" : "UNSTABLE"; }

std::string DescribeG1(const LinkModelFit& fit) {
  const IpmcLinkParams& p = fit.params;
  std::string text = FormatText("G1 = a0 / (b2 s^2 + b1 s + 1): a0 = %.5g mm/V, b1 = %.5g s, "
                            "b2 = %.5g s^2 (%s",
                            p.a0_mm_per_V, p.b1, p.b2_s2, StabilityText(fit).c_str());
  if (p.b2_s2 > 0 && p.b1 > 0) {
    text += FormatText("; zeta = %.4f, w_n = %.4g rad/s", p.b1 / (2 * std::sqrt(p.b2_s2)),
                   1 / std::sqrt(p.b2_s2));
  }
  return text + ")";
}

std::string DescribeG2(const LinkModelFit& fit, const LinkIdentification& id) {
  const IpmcLinkParams& p = fit.params;
  return FormatText("G2 = a0 / (b1 s^alpha + 1): alpha = %.2f, a0 = %.5g mm/V, b1 = %.5g s^alpha "
                "(%s; %d of %d orders stable)",
                p.alpha, p.a0_mm_per_V, p.b1, StabilityText(fit).c_str(), id.g2_orders_stable,
                id.g2_orders_tried);
}

std::string WelchDescription(const FrequencyResponseEstimate& e) {
  const double resolution_Hz = e.sample_rate_Hz / e.section_samples;
  return FormatText("Welch: %d record%s x %d sections of %d samples (%.4g s), %d-sample step "
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

// ------------------------------------------------------------ identify ---

int RunIdentify(const IdentifyArgs::Identify& args) {
  args.Validate();
  const CsvTable data = CsvTable::Read(args.data_path);
  const std::vector<double> input = data.FiniteNumbers(args.input_column);
  const std::vector<double> output = data.FiniteNumbers(args.output_column);
  std::optional<std::vector<double>> time_s;
  if (data.Has(columns::kTime)) time_s = data.FiniteNumbers(columns::kTime);
  const RecordIdentification result =
      IdentifyRecord(args, input, output, time_s ? &*time_s : nullptr);
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
                         ? FormatText("crossover %.4f rad/s, phase margin %.2f deg",
                                      *m.gain_crossover_rad_s, *m.phase_margin_deg)
                         : std::string("no gain crossover");
  text += m.gain_margin_db ? FormatText(", gain margin %.2f dB at %.4g rad/s", *m.gain_margin_db,
                                        *m.phase_crossover_rad_s)
                           : std::string(", no finite gain margin");
  return text;
}

std::string PidText(const PidGains& g) {
  return FormatText("C(s) = %.4g + %.4g/s + %.4g s", g.kp, g.ki, g.kd);
}

void PrintDesign(const DesignSpec& args) {
  const LinkDesign result = DesignLink(args);
  std::printf("plant: link %d, P = s^-0.5 %s (Table 2%s)\n", args.link,
              args.plant == "g2" ? "G2" : "G1",
              args.link == 3 && args.plant == "g1" ? ", eq. 7" : "");
  const FractionalIntegratorDesign& d = result.fractional.design;
  std::printf("fractional integrator for crossover %g rad/s, phase margin %g deg:\n",
              args.crossover_rad_s, args.phase_margin_deg);
  std::printf("  |P(j w_c)| = %.6g mm/V, arg P(j w_c) = %.4f deg\n", d.plant_magnitude,
              d.plant_phase_deg);
  std::printf("  C_I(s) = %.4f / s^%.4f  (lambda = (arg P + 180 - PM) / 90, K = w_c^lambda / "
              "|P|; paper eq. 14: %.2f / s^%.2f)\n",
              d.gain, d.order, kPaperFractional.gain, kPaperFractional.order);
  std::printf("  open loop (exact): %s\n", MarginsText(result.fractional.margins).c_str());

  const PidTuningResult& tuned = result.tuned;
  std::printf("PID tuned by Nelder-Mead against 1/((s/%g)^%g + 1), J of eq. 11 over %g s, loop "
              "sampled at %g Hz (linear, no clamp):\n",
              args.crossover_rad_s, args.reference_order, args.horizon_s, args.sample_rate_hz);
  std::printf("  %-34s %-34s %10s %10s %6s\n", "start", "result", "J_start", "J", "evals");
  for (const PidTuningRun& run : tuned.runs) {
    std::printf("  %-34s %-34s %10.6f %10.6f %6d%s\n", PidText(run.start).c_str(),
                PidText(run.gains).c_str(), run.start_cost, run.cost, run.evaluations,
                run.converged ? "" : " (not converged)");
  }
  std::printf("  paper (eq. 12): %s, J = %.6f\n", PidText(kPaperPid).c_str(), result.paper_cost);
  std::printf("  tuned:          %s, J = %.6f (%.1f %% of the paper's)\n",
              PidText(tuned.gains).c_str(), tuned.cost, 100 * tuned.cost / result.paper_cost);
  std::printf("  tuned open loop (exact plant, continuous PID): %s\n",
              MarginsText(result.pid_margins).c_str());
  std::printf("  tuning time %.2f s\n", result.tuning_s);
}

int RunDesign(const IdentifyArgs::Design& args) {
  ValidateLinkList(kDesignCommand, args.links);
  for (const int link : args.links) {
    if (link != args.links.front()) std::printf("\n");
    DesignSpec spec = args;
    spec.link = link;
    PrintDesign(spec);
  }
  return 0;
}

// ------------------------------------------------------------ pipeline ---

// The pipeline's validated settings.
struct PipelineSetup {
  BenchSignal signal;  // the chirp; driven_links set per run
  BenchIdentificationOptions identification;
  PidTuningOptions tuning;
  std::string model_path;
  bool drive_each = true;
};

// The simulated bench: one simulation per run, made (and attached) before
// the threads start.
struct PipelineBench {
  std::vector<std::unique_ptr<Simulation>> sims;
  std::vector<IpmcLinkParams> given;  // the simulator's link parameters
  int links = 0;
};

struct PipelineLink {
  int link = 0;                         // 1-based
  std::string measured;                 // what was measured
  BenchIdentification fit;
  std::optional<IpmcLinkParams> given;  // the simulator's parameters
  double identify_s = 0;                // Welch + Levy time
};

std::string Milli(double value) { return FormatText("%.4g", 1e3 * value); }

std::string Deviation(double identified, double given) {
  return FormatText("%+.1f %%", 100 * (identified / given - 1));
}

PipelineSetup ValidatePipeline(const IdentifyArgs::Pipeline& args) {
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
                FormatText("in (%g, %g) (above --f0-hz, below half the %g Hz sample rate)",
                           args.f0_hz, 0.5 * kBenchSampleRate_Hz, kBenchSampleRate_Hz),
                FormatDouble(args.f1_hz));
  }
  RequireFinitePositive(name, "--crossover-rad-s", args.crossover_rad_s);
  RequirePhaseMargin(name, args.phase_margin_deg);

  PipelineSetup setup;
  setup.identification.band = BandOptions(name, args.band_rad_s);
  setup.identification.repeats = args.repeats;
  setup.identification.noise_mm = args.noise_mm;
  setup.identification.seed = args.seed;
  setup.identification.sample_rate_Hz = kBenchSampleRate_Hz;
  setup.tuning = TuningOptions(name, args.crossover_rad_s, ReferenceModel::Config{}.order,
                               args.horizon_s, kPipelinePidRate_Hz);
  BenchSignal& signal = setup.signal;
  signal.kind = BenchSignal::Kind::kChirp;
  signal.amplitude_V = args.amplitude_v;
  signal.start_Hz = args.f0_hz;
  signal.end_Hz = args.f1_hz;
  signal.duration_s = args.duration_s;
  signal.sample_rate_Hz = kBenchSampleRate_Hz;
  signal.Validate();
  setup.model_path = args.model_path.empty()
                         ? ModelsDir() + "/flagellum3_clamped.xml"
                         : args.model_path;
  setup.drive_each = args.drive == kDriveEach;
  return setup;
}

// The model, checked for what the drive needs, once per run.
PipelineBench LoadPipelineBench(const PipelineSetup& setup) {
  const std::string name = kPipelineCommand;
  const std::string& path = setup.model_path;
  PipelineBench bench;
  bench.sims.push_back(std::make_unique<Simulation>(LoadModelFile(path), path));
  const std::optional<IpmcActuatorsConfig> config =
      IpmcActuatorsConfig::FromModel(bench.sims.front()->model());
  if (!config) throw std::invalid_argument(name + ": " + path + " has no IPMC actuators");
  bench.given = config->links;
  bench.links = static_cast<int>(config->links.size());
  if (setup.drive_each && config->actuation == Actuation::kSingle && bench.links > 1) {
    throw std::invalid_argument(name + ": --drive each needs distributed actuation, but " +
                                path + " has ipmc_actuation single");
  }
  const int runs = setup.drive_each ? bench.links : 1;
  for (int r = 1; r < runs; ++r) {
    bench.sims.push_back(std::make_unique<Simulation>(LoadModelFile(path), path));
  }
  return bench;
}

// The chirp on link r + 1 of run r, the runs in parallel threads.
std::vector<BenchRecord> RunBenches(const PipelineBench& bench, const BenchSignal& signal) {
  std::vector<BenchRecord> records(bench.sims.size());
  FanOut(records.size(), static_cast<int>(records.size()), [&](std::size_t r) {
    BenchSignal run_signal = signal;
    run_signal.driven_links = {static_cast<int>(r) + 1};
    records[r] = RunBench(*bench.sims[r], run_signal);
  });
  return records;
}

// Each link's identification: with --drive each, link q from its own run's
// voltage and relative deflection; with --drive first, every tip's lateral
// position against link 1's voltage.
std::vector<PipelineLink> IdentifyLinks(const PipelineSetup& setup, const PipelineBench& bench,
                                        const std::vector<BenchRecord>& records) {
  std::vector<PipelineLink> results;
  for (int q = 0; q < bench.links; ++q) {
    const Clock::time_point start = Clock::now();
    const BenchRecord& record = records[setup.drive_each ? q : 0];
    const int driven = setup.drive_each ? q : 0;
    PipelineLink result;
    result.link = q + 1;
    result.measured = setup.drive_each
                          ? columns::Relative(q + 1) + FormatText(" (link %d driven)", q + 1)
                          : columns::TipLateral(q + 1) + " (link 1 driven)";
    const std::vector<double>& output =
        setup.drive_each ? record.relative_mm[q] : record.tip_lateral_mm[q];
    result.fit = IdentifyBenchRecord(record.voltage_V[driven], output, setup.identification,
                                     static_cast<unsigned long long>(q));
    if (setup.drive_each || q == 0) result.given = bench.given[q];
    result.identify_s = Seconds(start);
    results.push_back(std::move(result));
  }
  return results;
}

// Section 5.2 on the identified G1 of `link`: both designs, as the
// report's table and J of eq. 11; `tuning_s` receives the PID tuning time.
std::string DesignSection(const PipelineLink& link, const IdentifyArgs::Pipeline& args,
                          const PidTuningOptions& tuning, double* tuning_s) {
  *tuning_s = 0;
  if (!link.fit.id.g1.stable) {
    return "The identified G1 of link " + std::to_string(link.link) +
           " is unstable: no controller designed.\n";
  }
  const IpmcLinkParams identified = link.fit.id.g1.params;
  const FrequencyFunction plant = [identified](double w) { return FittedResponse(identified, w); };
  std::string text = FormatText(
      "Plant: the identified P%d = s^-0.5 G1 of link %d. Specifications: crossover %g rad/s, "
      "phase margin %g deg; reference model 1/((s/%g)^%g + 1).\n\n",
      link.link, link.link, args.crossover_rad_s, args.phase_margin_deg, args.crossover_rad_s,
      tuning.reference.order);
  text += "| controller | on | gains | open loop |\n|---|---|---|---|\n";
  const FractionalLoopDesign fractional =
      DesignFractionalLoop(plant, args.crossover_rad_s, args.phase_margin_deg);
  text += FormatText("| fractional integrator (analytic) | identified | K = %.4f, lambda = %.4f "
                     "| %s |\n",
                     fractional.design.gain, fractional.design.order,
                     MarginsText(fractional.margins).c_str());
  if (link.given) {
    const IpmcLinkParams given = *link.given;
    const FractionalLoopDesign reference = DesignFractionalLoop(
        [given](double w) { return LinkResponseExact(given, w); }, args.crossover_rad_s,
        args.phase_margin_deg);
    text += FormatText("| fractional integrator (analytic) | simulator's model | K = %.4f, "
                       "lambda = %.4f | %s |\n",
                       reference.design.gain, reference.design.order,
                       MarginsText(reference.margins).c_str());
  }
  text += FormatText("| fractional integrator, paper eq. 14 | eq. 7 | K = %.2f, lambda = %.2f "
                     "| - |\n",
                     kPaperFractional.gain, kPaperFractional.order);
  const Clock::time_point start = Clock::now();
  const PidLoopDesign pid = DesignPidLoop(identified, plant, tuning);
  *tuning_s = Seconds(start);
  const PidGains& g = pid.tuned.gains;
  text += FormatText("| PID (Nelder-Mead, %zu starts) | identified | Kp = %.4g, Ki = %.4g, "
                     "Kd = %.4g | %s |\n",
                     pid.tuned.runs.size(), g.kp, g.ki, g.kd, MarginsText(pid.margins).c_str());
  text += FormatText("| PID, paper eq. 12 | eq. 7 | Kp = %.2f, Ki = %.2f, Kd = %.2f | - |\n\n",
                     kPaperPid.kp, kPaperPid.ki, kPaperPid.kd);
  text += FormatText("J of eq. 11 over %g s on the identified plant (unit step, loop sampled "
                     "at 10 kHz, linear): %.6f at the paper's gains, %.6f tuned (%.1f %%).\n",
                     args.horizon_s, pid.paper_cost, pid.tuned.cost,
                     100 * pid.tuned.cost / pid.paper_cost);
  return text;
}

// The report's first section: the experiment, the Welch set-up, the band.
std::string ExperimentSection(const IdentifyArgs::Pipeline& args, const PipelineSetup& setup,
                              int links, const std::vector<PipelineLink>& results) {
  const LevyOptions& band = setup.identification.band;
  std::string text = "# Identification of the simulated flagellum\n\n";
  text += FormatText("Model `%s`, %d IPMC links. Bench experiment (paper section 4.1): "
                     "%g V chirp from %g to %g Hz over %g s, recorded at %g Hz; ",
                     setup.model_path.c_str(), links, args.amplitude_v, args.f0_hz, args.f1_hz,
                     args.duration_s, kBenchSampleRate_Hz);
  text += setup.drive_each ? "each link driven in turn, its relative tip deflection "
                             "L_q sin(theta_q) measured.\n"
                           : "link 1 driven, the lateral position of every tip measured (the "
                             "paper's experiment).\n";
  text += FormatText("Repeats: %d, measurement noise %g mm (the simulator is deterministic: "
                     "repeats differ only by the noise).\n\n",
                     args.repeats, args.noise_mm);
  text += WelchDescription(results.front().fit.estimate) +
          FormatText(". Levy's method over [%g, %g] rad/s after removing s^-0.5; G2's alpha "
                     "swept over 1.01..1.99, the stable fit of least J kept.\n",
                     band.w_low_rad_s, band.w_high_rad_s);
  const std::string& first_note = results.front().fit.band_note;
  const bool same_notes =
      std::all_of(results.begin(), results.end(),
                  [&](const PipelineLink& r) { return r.fit.band_note == first_note; });
  if (same_notes && !first_note.empty()) {
    text += "\nAll links: " + first_note + ".\n";
  } else if (!same_notes) {
    for (const PipelineLink& r : results) {
      if (!r.fit.band_note.empty()) {
        text += "\nLink " + std::to_string(r.link) + ": " + r.fit.band_note + ".\n";
      }
    }
  }
  return text;
}

// Table 2's parameters as identified, beside the simulator's.
std::string ModelsSection(const std::vector<PipelineLink>& results, bool drive_each) {
  std::string text = "\n## Identified models (as Table 2)\n\n";
  text += "P = s^-0.5 G; a0 [1e-3 mm/V], b2 [1e-3 s^2], b1 [1e-3 s or s^alpha].\n\n";
  text += "| link | measured | model | alpha | a0 | b2 | b1 | stable |\n";
  text += "|---|---|---|---|---|---|---|---|\n";
  for (const PipelineLink& r : results) {
    const IpmcLinkParams& g1 = r.fit.id.g1.params;
    const IpmcLinkParams& g2 = r.fit.id.g2.params;
    text += FormatText("| %d | %s | G1 | - | %s | %s | %s | %s |\n", r.link, r.measured.c_str(),
                       Milli(g1.a0_mm_per_V).c_str(), Milli(g1.b2_s2).c_str(),
                       Milli(g1.b1).c_str(), r.fit.id.g1.stable ? "yes" : "no");
    if (r.given && r.given->kind == IpmcModelKind::kG1) {
      const IpmcLinkParams& s = *r.given;
      text += FormatText("| %d | | G1, simulator's | - | %s | %s | %s | |\n", r.link,
                         Milli(s.a0_mm_per_V).c_str(), Milli(s.b2_s2).c_str(),
                         Milli(s.b1).c_str());
      text += FormatText("| %d | | deviation | | %s | %s | %s | |\n", r.link,
                         Deviation(g1.a0_mm_per_V, s.a0_mm_per_V).c_str(),
                         Deviation(g1.b2_s2, s.b2_s2).c_str(), Deviation(g1.b1, s.b1).c_str());
    }
    text += FormatText("| %d | | G2 | %.2f | %s | - | %s | %s |\n", r.link, g2.alpha,
                       Milli(g2.a0_mm_per_V).c_str(), Milli(g2.b1).c_str(),
                       r.fit.id.g2.stable ? "yes" : "no");
    if (r.given && r.given->kind == IpmcModelKind::kG2) {
      const IpmcLinkParams& s = *r.given;
      text += FormatText("| %d | | G2, simulator's | %.2f | %s | - | %s | |\n", r.link, s.alpha,
                         Milli(s.a0_mm_per_V).c_str(), Milli(s.b1).c_str());
    }
  }
  if (!drive_each && results.size() > 1) {
    // Section 4.3: K_q = a0_q / a0_(q-1), each tip against the one before.
    text += "\nGains of each tip against the one before (a0 of G1, as section 4.3):";
    for (std::size_t q = 1; q < results.size(); ++q) {
      text += FormatText(" K%zu = %.3f", q + 1,
                         results[q].fit.id.g1.params.a0_mm_per_V /
                             results[q - 1].fit.id.g1.params.a0_mm_per_V);
    }
    text += ".\n";
  }
  return text;
}

// Table 3's indices of both fits per link.
std::string IndicesSection(const std::vector<PipelineLink>& results) {
  std::string text = "\n## Fit indices (as Table 3)\n\n";
  text += "On the complex P over the band points: J = sum |G D - N|^2 (Levy, [(mm/V)^2]), "
          "MSE = mean |e|^2, MAD = mean |e|, MD = max |e| [mm/V], "
          "R^2 = 1 - sum |e|^2 / sum |P - mean P|^2, e = P_measured - P_model.\n\n";
  text += "| link | model | points | J | MSE | MAD | MD | R^2 |\n";
  text += "|---|---|---|---|---|---|---|---|\n";
  for (const PipelineLink& r : results) {
    const std::pair<const char*, const LinkModelFit*> rows[] = {{"P1", &r.fit.id.g1},
                                                                {"P2", &r.fit.id.g2}};
    for (const auto& [label, fit] : rows) {
      const FitIndices& i = fit->indices;
      text += FormatText("| %d | %s | %d | %.4g | %.4g | %.4g | %.4g | %.4f |\n", r.link, label,
                         i.points, i.levy_cost, i.mse, i.mad, i.max_deviation, i.r_squared);
    }
  }
  return text;
}

std::string TimingSection(const std::vector<PipelineLink>& results,
                          const IdentifyArgs::Pipeline& args, std::size_t runs, double bench_s,
                          double tuning_s) {
  std::string text = "\n## Timing\n\n";
  text += FormatText("Bench simulation: %.2f s wall for %zu run%s of %g s%s. "
                     "Welch and Levy (with the alpha sweep) per link:",
                     bench_s, runs, runs == 1 ? "" : "s", args.duration_s,
                     runs == 1 ? "" : " in parallel threads");
  for (const PipelineLink& r : results) text += FormatText(" %.3f s", r.identify_s);
  text += FormatText(". PID tuning: %.2f s.\n", tuning_s);
  return text;
}

// DIR/response_link<q>.csv and DIR/report.md.
void WritePipelineFiles(const std::string& out_dir, const std::vector<PipelineLink>& results,
                        const std::string& report) {
  EnsureDirectory(out_dir);
  const std::filesystem::path dir(out_dir);
  for (const PipelineLink& r : results) {
    WriteFileAtomically((dir / ("response_link" + std::to_string(r.link) + ".csv")).string(),
                        ResponseCsv(r.fit.estimate, r.fit.id));
  }
  WriteFileAtomically((dir / "report.md").string(), report);
}

int RunPipeline(const IdentifyArgs::Pipeline& args) {
  const PipelineSetup setup = ValidatePipeline(args);
  const PipelineBench bench = LoadPipelineBench(setup);
  const Clock::time_point bench_start = Clock::now();
  const std::vector<BenchRecord> records = RunBenches(bench, setup.signal);
  const double bench_s = Seconds(bench_start);
  const std::vector<PipelineLink> results = IdentifyLinks(setup, bench, records);

  // The designs on the identified model of link 3 (or the last link).
  const PipelineLink& design_link = results[std::min(3, bench.links) - 1];
  double tuning_s = 0;
  const std::string design = DesignSection(design_link, args, setup.tuning, &tuning_s);
  const std::string report =
      ExperimentSection(args, setup, bench.links, results) +
      ModelsSection(results, setup.drive_each) + IndicesSection(results) +
      "\n## Controllers for link " + std::to_string(design_link.link) + " (section 5.2)\n\n" +
      design + TimingSection(results, args, records.size(), bench_s, tuning_s);
  std::printf("%s", report.c_str());
  if (!args.out_dir.empty()) WritePipelineFiles(args.out_dir, results, report);
  return 0;
}

}  // namespace

void AddIdentifyCommands(CLI::App& app, IdentifyArgs& args) {
  IdentifyArgs::Identify& i = args.identify;
  CLI::App* identify = AddCommand(
      app, kIdentifyCommand,
      "Frequency response (Welch) and Levy fits of G1 and G2 from bench data");
  identify->add_option("data", i.data_path, "CSV file with a header row")->required();
  identify->add_option("--input", i.input_column, "Input column, e.g. voltage1_V")->required();
  identify->add_option("--output", i.output_column, "Output column, e.g. relative3_mm")
      ->required();
  identify->add_option("--sample-rate-hz", i.sample_rate_hz, "Sample rate [Hz]");
  identify->add_option("--band-rad-s", i.band_rad_s, "Identification band LOW,HIGH [rad/s]")
      ->delimiter(',');
  identify->add_option("-o,--out", i.out_dir, "Directory for response.csv and identification.json");

  IdentifyArgs::Design& d = args.design;
  CLI::App* design = AddCommand(
      app, kDesignCommand, "Fractional integrator (analytic) and PID (Nelder-Mead) for each link");
  design->add_option("--links", d.links, "Links to design for, e.g. 3 or 1,2,3 (Table 2)")
      ->delimiter(',');
  AddPlantOption(design, d.plant);
  design->add_option("--crossover-rad-s", d.crossover_rad_s, "Gain crossover w_c [rad/s]");
  design->add_option("--phase-margin-deg", d.phase_margin_deg, "Phase margin [deg]");
  design->add_option("--reference-order", d.reference_order,
                     "Reference model order gamma, in (0, 2]");
  design->add_option("--horizon-s", d.horizon_s, "Horizon of J (eq. 11) [s]");
  design->add_option("--sample-rate-hz", d.sample_rate_hz, "PID rate in the tuning loop [Hz]");

  IdentifyArgs::Pipeline& p = args.pipeline;
  CLI::App* pipeline = AddCommand(
      app, kPipelineCommand,
      "Bench chirp on the simulated clamped flagellum, identification and design, as a report");
  pipeline->add_option("--model", p.model_path,
                       "MJCF model with IPMC actuators (default models/flagellum3_clamped.xml)");
  pipeline->add_option("--drive", p.drive,
                       "each: each link in turn, its relative deflection | first: link 1, every "
                       "tip (the paper)")
      ->check(CLI::IsMember({kDriveEach, kDriveFirst}));
  pipeline->add_option("--duration-s", p.duration_s, "Chirp duration [s]");
  pipeline->add_option("--amplitude-v", p.amplitude_v, "Chirp amplitude [V]");
  pipeline->add_option("--f0-hz", p.f0_hz, "Chirp start frequency [Hz]");
  pipeline->add_option("--f1-hz", p.f1_hz, "Chirp end frequency [Hz]");
  pipeline->add_option("--repeats", p.repeats, "Records per link (differ by the noise only)");
  pipeline->add_option("--noise-mm", p.noise_mm, "Measurement noise standard deviation [mm]");
  pipeline->add_option("--seed", p.seed, "Noise seed");
  pipeline->add_option("--band-rad-s", p.band_rad_s, "Identification band LOW,HIGH [rad/s]")
      ->delimiter(',');
  pipeline->add_option("--crossover-rad-s", p.crossover_rad_s, "Design crossover w_c [rad/s]");
  pipeline->add_option("--phase-margin-deg", p.phase_margin_deg, "Design phase margin [deg]");
  pipeline->add_option("--horizon-s", p.horizon_s, "Horizon of J (eq. 11) [s]");
  pipeline->add_option("-o,--out", p.out_dir, "Directory for report.md and response_link<q>.csv");
}

int RunIdentifyCommand(const CLI::App& app, const IdentifyArgs& args) {
  if (app.got_subcommand(kIdentifyCommand)) return RunIdentify(args.identify);
  if (app.got_subcommand(kDesignCommand)) return RunDesign(args.design);
  if (app.got_subcommand(kPipelineCommand)) return RunPipeline(args.pipeline);
  return -1;
}

}  // namespace ipmc
