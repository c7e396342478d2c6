#include "sim/identify/pipeline_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "controllers/fractional_integrator.h"
#include "sim/linear/frequency_response.h"
#include "controllers/reference_model.h"
#include "ipmc_swim/fields.h"
#include "sim/core/scenario_simulation.h"
#include "sim/linear/ipmc_link_model.h"
#include "sim/core/data_paths.h"
#include "sim/core/fan_out.h"
#include "sim/core/simulation.h"
#include "sim/identify/bench_identification.h"
#include "sim/identify/controller_design.h"
#include "sim/identify/identify_run.h"
#include "sim/identify/levy.h"
#include "sim/identify/report_text.h"
#include "sim/identify/welch.h"
#include "sim/io/columns.h"
#include "sim/base/error.h"
#include "sim/io/files.h"
#include "sim/base/numbers.h"
#include "sim/runs/bench_run.h"

namespace ipmc {
namespace {

using Clock = std::chrono::steady_clock;

constexpr char kPipelineCommand[] = "pipeline";
constexpr char kDriveEach[] = "each";
constexpr char kDriveFirst[] = "first";

// The bench records at the data-acquisition board's rate.
constexpr double kBenchSampleRate_Hz = 1000.0;
// The PID's rate in the pipeline's tuning loop.
constexpr double kPipelinePidRate_Hz = 1e4;
// Bounds on the options that size the work.
constexpr double kMaxDuration_s = 1e4;
constexpr int kMaxRepeats = 100;
constexpr double kMaxAmplitude_V = 100.0;  // as BenchSignal

double Seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

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

PipelineSetup ValidatePipeline(const PipelineCommand& args) {
  const std::string name = kPipelineCommand;
  if (args.drive != kDriveEach && args.drive != kDriveFirst) {
    ThrowOption(name, "drive", "each or first", "'" + args.drive + "'");
  }
  RequireFinitePositive(name, "duration_s", args.duration_s);
  if (args.duration_s > kMaxDuration_s) {
    ThrowOption(name, "duration_s", "at most " + FormatDouble(kMaxDuration_s),
                FormatDouble(args.duration_s));
  }
  if (args.repeats < 1 || args.repeats > kMaxRepeats) {
    ThrowOption(name, "repeats", "in [1, " + std::to_string(kMaxRepeats) + "]",
                std::to_string(args.repeats));
  }
  if (!std::isfinite(args.noise_mm) || args.noise_mm < 0) {
    ThrowOption(name, "noise_mm", "finite and >= 0", FormatDouble(args.noise_mm));
  }
  if (!std::isfinite(args.amplitude_V) || args.amplitude_V == 0 ||
      std::abs(args.amplitude_V) > kMaxAmplitude_V) {
    ThrowOption(name, "amplitude_V", "finite, nonzero and within +-" +
                FormatDouble(kMaxAmplitude_V), FormatDouble(args.amplitude_V));
  }
  RequireFinitePositive(name, "start_Hz", args.start_Hz);
  if (!std::isfinite(args.end_Hz) || !(args.end_Hz > args.start_Hz) ||
      !(args.end_Hz < 0.5 * kBenchSampleRate_Hz)) {
    ThrowOption(name, "end_Hz",
                FormatText("in (%g, %g) (above start_Hz, below half the %g Hz sample rate)",
                           args.start_Hz, 0.5 * kBenchSampleRate_Hz, kBenchSampleRate_Hz),
                FormatDouble(args.end_Hz));
  }
  RequireFinitePositive(name, "crossover_rad_s", args.crossover_rad_s);
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
  signal.amplitude_V = args.amplitude_V;
  signal.start_Hz = args.start_Hz;
  signal.end_Hz = args.end_Hz;
  signal.duration_s = args.duration_s;
  signal.sample_rate_Hz = kBenchSampleRate_Hz;
  signal.Validate();
  setup.model_path = args.model.empty()
                         ? ModelsDir() + "/flagellum3_clamped.xml"
                         : args.model;
  setup.drive_each = args.drive == kDriveEach;
  return setup;
}

// The model, checked for what the drive needs, once per run.
PipelineBench LoadPipelineBench(const PipelineSetup& setup) {
  const std::string name = kPipelineCommand;
  const std::string& path = setup.model_path;
  PipelineBench bench;
  bench.sims.push_back(std::make_unique<Simulation>(LoadModelFile(path), path));
  bench.given = AttachedLinkPlants(bench.sims.front()->data());
  if (bench.given.empty()) throw std::invalid_argument(name + ": " + path + " has no IPMC actuators");
  bench.links = static_cast<int>(bench.given.size());
  if (setup.drive_each && ModelActuation(bench.sims.front()->model()) == Actuation::kSingle &&
      bench.links > 1) {
    throw FieldError(name + ": drive each needs distributed actuation, but " + path +
                         " has ipmc_actuation single",
                     "drive", "first, for a model with single actuation");
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

// Each link's identification: with drive each, link q from its own run's
// voltage and relative deflection; with drive first, every tip's lateral
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
    try {
      result.fit = IdentifyBenchRecord(record.voltage_V[driven], output, setup.identification,
                                       static_cast<unsigned long long>(q));
    } catch (const std::invalid_argument& error) {
      // E.g. noise so large that the spectra overflow: nothing is written.
      throw std::invalid_argument(FormatText("%s: link %d's record (noise_mm %g): %s",
                                             kPipelineCommand, q + 1,
                                             setup.identification.noise_mm, error.what()));
    }
    if (setup.drive_each || q == 0) result.given = bench.given[q];
    result.identify_s = Seconds(start);
    results.push_back(std::move(result));
  }
  return results;
}

// Section 5.2 on the identified G1 of `link`: both designs, as the
// report's table and J of eq. 11; `tuning_s` receives the PID tuning time.
std::string DesignSection(const PipelineLink& link, const PipelineCommand& args,
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
std::string ExperimentSection(const PipelineCommand& args, const PipelineSetup& setup,
                              int links, const std::vector<PipelineLink>& results) {
  const LevyOptions& band = setup.identification.band;
  std::string text = "# Identification of the simulated flagellum\n\n";
  text += FormatText("Model `%s`, %d IPMC links. Bench experiment (paper section 4.1): "
                     "%g V chirp from %g to %g Hz over %g s, recorded at %g Hz; ",
                     setup.model_path.c_str(), links, args.amplitude_V, args.start_Hz, args.end_Hz,
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
                          const PipelineCommand& args, std::size_t runs, double bench_s,
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

OptionTable<PipelineCommand> MakePipelineOptions() {
  OptionTable<PipelineCommand> table(
      kPipelineCommand,
      "Bench chirp on the simulated clamped flagellum, identification and design, as a report");
  OptionInfo model{"model", "", "an MJCF file with IPMC actuators", "The model"};
  model.default_text = "models/flagellum3_clamped.xml";
  table.AddPath(model,
                [](PipelineCommand& c) -> std::string& { return c.model; });
  OptionInfo drive{"drive", "", "",
                   "each: each link in turn, its relative deflection | first: link 1, every tip "
                   "(the paper)"};
  drive.choices = {kDriveEach, kDriveFirst};
  table.Add<std::string>(drive, [](PipelineCommand& c) -> std::string& { return c.drive; });
  table.Add<double>({"duration_s", "s", "in (0, 1e4]", "Chirp duration"},
                    [](PipelineCommand& c) -> double& { return c.duration_s; });
  table.Add<double>({"amplitude_V", "V", "finite, nonzero, within +-100", "Chirp amplitude"},
                    [](PipelineCommand& c) -> double& { return c.amplitude_V; });
  OptionInfo start{"start_Hz", "Hz", "finite and > 0", "Chirp start frequency f0"};
  start.aliases = {"f0_Hz"};
  table.Add<double>(start, [](PipelineCommand& c) -> double& { return c.start_Hz; });
  OptionInfo end{"end_Hz", "Hz", "above start_Hz, below 500 Hz", "Chirp end frequency f1"};
  end.aliases = {"f1_Hz"};
  table.Add<double>(end, [](PipelineCommand& c) -> double& { return c.end_Hz; });
  table.Add<int>({"repeats", "", "in [1, 100]", "Records per link (differ by the noise only)"},
                 [](PipelineCommand& c) -> int& { return c.repeats; });
  table.Add<double>({"noise_mm", "mm", "finite and >= 0",
                     "Measurement noise standard deviation"},
                    [](PipelineCommand& c) -> double& { return c.noise_mm; });
  table.Add<unsigned>({"seed", "", ">= 0", "Noise seed"},
                      [](PipelineCommand& c) -> unsigned& { return c.seed; });
  table.Add<std::vector<double>>(
      {"band_rad_s", "rad/s", "LOW,HIGH with 0 < LOW < HIGH", "Identification band"},
      [](PipelineCommand& c) -> std::vector<double>& { return c.band_rad_s; });
  table.Add<double>({"crossover_rad_s", "rad/s", "finite and > 0", "Design crossover w_c"},
                    [](PipelineCommand& c) -> double& { return c.crossover_rad_s; });
  table.Add<double>({"phase_margin_deg", "deg", "in (0, 180)", "Design phase margin"},
                    [](PipelineCommand& c) -> double& { return c.phase_margin_deg; });
  table.Add<double>({"horizon_s", "s", "finite and > 0", "Horizon of J (eq. 11)"},
                    [](PipelineCommand& c) -> double& { return c.horizon_s; });
  OptionInfo out{"out", "", "a folder", "Folder for report.md and response_link<q>.csv"};
  out.aliases = {"o"};
  table.AddPath(out, [](PipelineCommand& c) -> std::string& { return c.out; });
  return table;
}

}  // namespace

const OptionTable<PipelineCommand>& PipelineOptions() {
  static const OptionTable<PipelineCommand> table = MakePipelineOptions();
  return table;
}

std::string RunPipelineCommand(const PipelineCommand& args) {
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
  if (!args.out.empty()) WritePipelineFiles(args.out, results, report);
  return report;
}

}  // namespace ipmc
