// ipmc-swim command-line program.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/cli/analysis_commands.h"
#include "sim/cli/command.h"
#include "sim/cli/interrupt.h"
#include "sim/cli/run_watch.h"
#include "sim/batch/sweep.h"
#include "plugin/base/error.h"
#include "sim/io/files.h"
#include "sim/io/toml.h"
#include "sim/runs/bench_run.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/core/gait.h"
#include "sim/cli/identify_command.h"
#include "sim/runs/gait_run.h"
#include "sim/core/model_generator.h"
#include "sim/runs/output.h"
#include "sim/cli/plot_command.h"
#include "sim/core/scenario.h"
#include "sim/core/scenario_overrides.h"
#include "sim/cli/keys_command.h"
#include "sim/cli/sweep_command.h"
#include "sim/cli/table5_command.h"
#include "sim/cli/render_command.h"
#include "sim/core/data_paths.h"
#include "sim/core/simulation.h"

namespace {

using ipmc::FlagellumSpec;

// MuJoCo's warnings, held back so that a failing run prints one line.
std::vector<std::string>& MujocoWarnings() {
  static std::vector<std::string> warnings;
  return warnings;
}
void CollectMujocoWarning(const char* message) { MujocoWarnings().emplace_back(message); }
void PrintMujocoWarnings() {
  for (const std::string& warning : MujocoWarnings()) {
    std::cerr << "ipmc-swim: MuJoCo warning: " << warning << "\n";
  }
}

// --allow-long: lifts the run size limits (sim/core/step_count.h).
void AddAllowLongFlag(CLI::App* cmd, bool& allow) {
  cmd->add_flag("--allow-long", allow,
                "Run even beyond 1e8 steps or 2 GB of recorded samples (refused otherwise, with "
                "the estimate)");
}

struct GenerateArgs {
  FlagellumSpec spec;
  std::string out_path;
};

void AddGenerateCommand(CLI::App& app, GenerateArgs& args) {
  CLI::App* cmd = ipmc::AddCommand(app, "generate", "Write the MJCF of an N-link flagellum");
  FlagellumSpec& s = args.spec;
  cmd->add_option("--links-mm", s.link_lengths_mm, "Link lengths [mm], one per link")
      ->delimiter(',');
  cmd->add_option("--gap-mm", s.gap_mm, "Gap between links [mm]");
  cmd->add_option("--width-mm", s.width_mm, "Strip width [mm]");
  cmd->add_option("--thickness-um", s.thickness_um, "Strip thickness [um]");
  cmd->add_option("--head-mm", s.head_length_mm, "Head (clamp) length [mm], 0 for none");
  cmd->add_option("--density", s.density_kg_m3, "Density [kg/m^3]");
  cmd->add_option("--modulus-pa", s.bending_modulus_Pa, "Bending modulus E [Pa]");
  cmd->add_option("--hinge-damping-ratio", s.hinge_damping_ratio, "Hinge damping ratio zeta_h");
  cmd->add_flag("--clamped", s.clamped, "Weld the root (test bench)");
  cmd->add_option("--timestep-s", s.timestep_s, "Time step [s]");
  cmd->add_option("--integrator", s.integrator, "Euler | implicit | RK4");
  cmd->add_option("--viscosity-pa-s", s.viscosity_Pa_s, "Viscosity [Pa s]");
  cmd->add_option("--coefficients", s.coefficients, "gray_hancock | lighthill | direct");
  cmd->add_option("--wavelength-mm", s.wavelength_mm, "Wavelength for the RFT coefficients [mm]");
  cmd->add_option("--xi-normal", s.xi_normal_N_s_m2, "Direct xi_n [N s/m^2]")
      ->default_str("");
  cmd->add_option("--xi-tangential", s.xi_tangential_N_s_m2, "Direct xi_t [N s/m^2]")
      ->default_str("");
  cmd->add_option("--segments-per-link", s.segments_per_link,
                  "Rigid sub-segments per link (1: rigid links)");
  cmd->add_option("--plants", s.plants,
                  "uniform (every link eq. 7's plant) | table2 (Table 2's row per link)");
  cmd->add_option("--ipmc-model", s.ipmc_model, "IPMC link model: g1 (eq. 5) | g2 (eq. 6)");
  cmd->add_option("--actuation", s.actuation, "distributed | single");
  cmd->add_option("--name", s.name, "Model name");
  cmd->add_option("-o,--out", args.out_path, "Output MJCF file (default: stdout)");
}

struct GaitArgs {
  std::string model_path = ipmc::ModelsDir() + "/flagellum3.xml";
  std::string gait = "sine";
  double frequency_Hz = 0.01;
  double amplitude_rad = 0.3;
  double phase_lag_rad = 2.0;
  std::vector<double> amplitudes_rad;
  std::vector<double> phases_rad;
  std::string csv_path;
  ipmc::GaitRunOptions run;
  std::string out_dir;
};

void AddGaitCommand(CLI::App& app, GaitArgs& args) {
  CLI::App* cmd = ipmc::AddCommand(app, "gait", "Run a prescribed joint-space gait and measure the swim");
  cmd->add_option("--model", args.model_path, "MJCF model with servo_* actuators");
  cmd->add_option("--gait", args.gait, "sine | square | csv")
      ->check(CLI::IsMember({"sine", "square", "csv"}));
  cmd->add_option("--frequency-hz", args.frequency_Hz, "Gait frequency [Hz]");
  cmd->add_option("--amplitude-rad", args.amplitude_rad, "Joint amplitude [rad]");
  cmd->add_option("--phase-lag-rad", args.phase_lag_rad,
                  "Sine: phase lag between consecutive joints [rad]; > 0 sends the wave to the tail");
  cmd->add_option("--amplitudes-rad", args.amplitudes_rad, "Sine: per-joint amplitudes [rad]")
      ->delimiter(',')
      ->default_str("");
  cmd->add_option("--phases-rad", args.phases_rad, "Sine: per-joint phases [rad]")->delimiter(',')
      ->default_str("");
  cmd->add_option("--csv", args.csv_path, "CSV gait: time_s, q_1..q_n [rad]");
  cmd->add_option("--cycles", args.run.cycles, "Number of gait cycles");
  cmd->add_option("--samples-per-cycle", args.run.samples_per_cycle, "Time-series samples per cycle");
  cmd->add_option("-o,--out", args.out_dir, "Directory for timeseries.csv and summary.json");
  AddAllowLongFlag(cmd, args.run.allow_long);
}

struct BenchArgs {
  std::string model_path = ipmc::ModelsDir() + "/flagellum3_clamped.xml";
  std::string signal = "sine";
  ipmc::BenchSignal bench;
  std::string out_path;
};

void AddBenchCommand(CLI::App& app, BenchArgs& args) {
  CLI::App* cmd = ipmc::AddCommand(
      app, "bench", "Voltage experiment on the test bench, recorded like the laser meter");
  ipmc::BenchSignal& b = args.bench;
  cmd->add_option("--model", args.model_path, "MJCF model with IPMC actuators");
  cmd->add_option("--signal", args.signal, "sine | chirp")
      ->check(CLI::IsMember({"sine", "chirp"}));
  cmd->add_option("--amplitude-v", b.amplitude_V, "Voltage amplitude [V]");
  cmd->add_option("--frequency-hz", b.frequency_Hz, "Sine frequency [Hz]");
  cmd->add_option("--f0-hz", b.start_Hz, "Chirp start frequency [Hz]");
  cmd->add_option("--f1-hz", b.end_Hz, "Chirp end frequency [Hz]");
  cmd->add_option("--duration-s", b.duration_s, "Duration [s]");
  cmd->add_option("--links", b.driven_links, "Driven links, 1-based")->delimiter(',');
  cmd->add_option("--sample-rate-hz", b.sample_rate_Hz, "Voltage update and recording rate [Hz]");
  cmd->add_option("-o,--out", args.out_path, "CSV file to write")->required();
  AddAllowLongFlag(cmd, b.allow_long);
}

int RunBenchCommand(BenchArgs args) {
  args.bench.kind = args.signal == "chirp" ? ipmc::BenchSignal::Kind::kChirp
                                           : ipmc::BenchSignal::Kind::kSine;
  args.bench.Validate();
  ipmc::RefuseOverwritingInputs("bench", "--out", args.out_path, {args.model_path});
  ipmc::RequireWritableParent(args.out_path);
  ipmc::Simulation sim(ipmc::LoadModelFile(args.model_path), args.model_path);
  ipmc::RunWatch watch("bench", args.bench.duration_s);
  const ipmc::BenchRecord record =
      ipmc::RunBench(sim, args.bench, 0.0, [&](double t_s) { watch.At(t_s); });
  watch.Finish();
  ipmc::WriteFileAtomically(args.out_path, ipmc::BenchCsv(record));
  std::printf("%zu samples at %g Hz written to %s\n", record.t_s.size(),
              args.bench.sample_rate_Hz, args.out_path.c_str());
  for (size_t q = 0; q < record.relative_mm.size(); ++q) {
    double peak = 0.0;
    for (double value : record.relative_mm[q]) peak = std::max(peak, std::abs(value));
    std::printf("link %zu: peak relative tip deflection %.6g mm\n", q + 1, peak);
  }
  return 0;
}

void PrintSwimMetrics(const ipmc::SwimMetrics& swim);

struct RunArgs {
  std::string scenario_path;
  std::vector<std::string> sets;  // --set KEY=VALUE, in order
  int cycles = 0;                 // --cycles, if given
  std::string out_dir;
  std::string video_path;
  ipmc::FilmConfig film;
  bool allow_long = false;
  std::vector<std::string> formats;  // --format, besides CSV and JSON
  CLI::App* command = nullptr;
};

void AddRunCommand(CLI::App& app, RunArgs& args) {
  CLI::App* cmd = ipmc::AddCommand(app, "run", "Run a closed-loop scenario file (TOML)");
  cmd->add_option("scenario", args.scenario_path,
                  "Scenario file (TOML), or a run's summary.json to run it again")
      ->required();
  cmd->add_option("--set", args.sets,
                  "KEY=VALUE: set a scenario key (dotted, as in sweep files; VALUE is TOML: "
                  "strings in quotes); repeatable; see `ipmc-swim keys`")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  cmd->add_option("--cycles", args.cycles, "Wave periods to run (= --set cycles=N)");
  cmd->add_option("-o,--out", args.out_dir, "Output directory (overrides output.dir)");
  cmd->add_option("--format", args.formats,
                  "Also write the whole run as run.mat (mat: MATLAB/Octave) or run.h5 (h5: "
                  "HDF5); repeatable or comma-separated; csv (always written) is accepted")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  cmd->add_option("--video", args.video_path,
                  "Also film the run into this MP4 (from its recorded states; see `render`)");
  AddAllowLongFlag(cmd, args.allow_long);
  ipmc::AddVideoOptions(cmd, args.film, "Video (with --video)", "--film-cycles");
  args.command = cmd;
}

void PrintClosedLoopResult(const ipmc::ClosedLoopResult& r) {
  std::printf("%s controller, %s actuation, wave period %.6g s, time step %.3g s\n",
              r.controller.c_str(), r.actuation.c_str(), r.period_s, r.timestep_s);
  std::printf("%4s %12s %14s %14s %12s %12s %10s\n", "link", "IAE_mm_s", "ITAE_mm_s2",
              "max_error_mm", "max_ref_mm", "rms_V", "clamped_%");
  for (size_t q = 0; q < r.links.size(); ++q) {
    const ipmc::LinkTracking& t = r.links[q];
    std::printf("%4zu %12.5g %14.6g %14.5g %12.5g %12.4g %10.1f\n", q + 1, t.iae_mm_s,
                t.itae_mm_s2, t.max_abs_error_mm, t.max_abs_reference_mm, t.rms_voltage_V,
                100.0 * t.saturated_fraction);
  }
  PrintSwimMetrics(r.swim);
}

// Where a run's outputs went (sim/runs/output.h).
void PrintWritten(const std::string& dir, const ipmc::RunFileFormats& formats = {}) {
  std::string extra;
  if (formats.mat) extra += std::string(", ") + ipmc::kRunMatFile;
  if (formats.hdf5) extra += std::string(", ") + ipmc::kRunHdf5File;
  std::printf("wrote %s/timeseries.csv, states.csv%s and summary.json\n", dir.c_str(),
              extra.c_str());
}

// A path made absolute, so that a run's outputs name their inputs from
// anywhere (render reads them back).
std::string AbsolutePath(const std::string& path) {
  return std::filesystem::absolute(path).lexically_normal().string();
}

bool IsRunSummary(const std::string& path) {
  return std::filesystem::path(path).extension() == ".json";
}

// The scenario file with the --set and --cycles settings
// (ScenarioWithSettings, sim/core/scenario_overrides.h).
ipmc::ScenarioConfig ScenarioWithOptions(const RunArgs& args) {
  std::vector<ipmc::ScenarioSetting> settings;
  for (const std::string& set : args.sets) settings.push_back(ipmc::SetOption("run", set));
  if (args.command->count("--cycles") > 0) {
    const std::string cycles = std::to_string(args.cycles);
    settings.push_back({"--cycles " + cycles, "cycles=" + cycles});
  }
  return ipmc::ScenarioWithSettings("run", args.scenario_path, settings);
}

int RunScenarioCommand(const RunArgs& args) {
  if (args.video_path.empty() && ipmc::AnyVideoOptionGiven(args.command)) {
    throw std::invalid_argument("run: video options need --video FILE.mp4");
  }
  const bool rerun = IsRunSummary(args.scenario_path);
  const bool overridden = !args.sets.empty() || args.command->count("--cycles") > 0;
  if (rerun && overridden) {
    throw std::invalid_argument(
        "run: --set and --cycles apply to scenario files, not to a run's summary.json");
  }
  ipmc::ScenarioConfig scenario =
      rerun ? ipmc::ScenarioOfSummary(args.scenario_path)
            : overridden ? ScenarioWithOptions(args) : ipmc::LoadScenario(args.scenario_path);
  scenario.allow_long_run = args.allow_long;
  nlohmann::json inputs = {{"scenario", AbsolutePath(args.scenario_path)}};
  if (rerun) inputs = {{"rerun_of", AbsolutePath(args.scenario_path)}};
  if (!args.sets.empty()) inputs["set"] = args.sets;
  if (args.command->count("--cycles") > 0) inputs["cycles"] = args.cycles;
  // A re-run writes only where --out says, never over the run it repeats.
  const std::string dir = args.out_dir.empty() && !rerun ? scenario.output_dir : args.out_dir;
  const ipmc::RunFileFormats formats = ipmc::ParseRunFileFormats(args.formats);
  if ((formats.mat || formats.hdf5) && dir.empty()) {
    throw std::invalid_argument("run: --format mat or h5 needs an output directory (--out DIR)");
  }
  // Output locations are checked before the run, not after it.
  if (!dir.empty()) ipmc::CheckRunOutputDirectory("run", "--out", dir, {args.scenario_path});
  if (!args.video_path.empty()) {
    ipmc::RefuseOverwritingInputs("run", "--video", args.video_path, {args.scenario_path});
    ipmc::RequireWritableParent(args.video_path);
  }
  // One run per output directory, from the start of the work to its end.
  std::optional<ipmc::DirectoryLock> hold;
  if (!dir.empty()) hold.emplace(dir);
  // The results are printed and written before the film is made.
  ipmc::RunScenarioFilmed(scenario, args.film, args.video_path,
                          [&](const ipmc::ClosedLoopResult& result) {
                            PrintClosedLoopResult(result);
                            if (dir.empty()) return;
                            ipmc::WriteClosedLoopOutputs(dir, result, scenario, inputs, formats);
                            PrintWritten(dir, formats);
                          });
  return 0;
}

int CountServos(const mjModel* m) {
  int count = 0;
  for (int a = 0; a < m->nu; ++a) {
    const char* name = mj_id2name(m, mjOBJ_ACTUATOR, a);
    if (name && std::string(name).rfind("servo_", 0) == 0) ++count;
  }
  return count;
}

std::unique_ptr<ipmc::Gait> MakeGait(const GaitArgs& args, int joints) {
  if (args.gait == "csv") {
    if (args.csv_path.empty()) throw std::invalid_argument("gait: --gait csv needs --csv PATH");
    return ipmc::LoadCsvGait(args.csv_path, joints);
  }
  if (args.gait == "square") {
    ipmc::SquareStrokeConfig config;
    config.frequency_Hz = args.frequency_Hz;
    config.amplitude_rad = args.amplitude_rad;
    config.joints = joints;
    return ipmc::MakeSquareStroke(config);
  }
  ipmc::SineGaitConfig config =
      ipmc::TravellingWave(joints, args.frequency_Hz, args.amplitude_rad, args.phase_lag_rad);
  if (!args.amplitudes_rad.empty()) config.amplitude_rad = args.amplitudes_rad;
  if (!args.phases_rad.empty()) config.phase_rad = args.phases_rad;
  if (static_cast<int>(config.amplitude_rad.size()) != joints) {
    throw std::invalid_argument("gait: --amplitudes-rad needs " + std::to_string(joints) +
                                " values (one per driven joint)");
  }
  return ipmc::MakeSineGait(config);
}

void PrintSwimMetrics(const ipmc::SwimMetrics& swim) {
  std::printf("%5s %14s %14s %14s %14s\n", "cycle", "com_along_mm", "com_across_mm",
              "head_along_mm", "head_across_mm");
  for (size_t k = 0; k < swim.per_cycle.size(); ++k) {
    const ipmc::Displacement_mm& c = swim.per_cycle[k];
    std::printf("%5zu %14.6g %14.6g %14.6g %14.6g\n", k + 1, c.com_along, c.com_across,
                c.head_along, c.head_across);
  }
  std::printf("mean speed along the swimming axis: %.6g mm/s\n", swim.mean_speed_along_mm_s);
  std::printf("Reynolds number: %.3g (peak lateral tip speed x width), %.3g (mean speed x length)\n",
              swim.reynolds_tip, swim.reynolds_swim);
  if (swim.reynolds_tip > 1.0 || swim.reynolds_swim > 1.0) {
    std::fprintf(stderr, "warning: Reynolds number above 1; resistive-force theory assumes Re << 1\n");
  }
}

void PrintGaitResult(const ipmc::GaitRunResult& r) {
  std::printf("%s, period %.6g s, time step %.3g s\n", r.gait.c_str(), r.period_s, r.timestep_s);
  PrintSwimMetrics(r.swim);
  std::printf("servo tracking: max error %.3g rad for references up to %.3g rad\n",
              r.max_tracking_error_rad, r.max_reference_rad);
}

int RunGenerate(const GenerateArgs& args) {
  const std::string xml = ipmc::GenerateFlagellumMjcf(args.spec);
  if (args.out_path.empty()) {
    std::cout << xml;
  } else {
    ipmc::WriteFileAtomically(args.out_path, xml);
  }
  return 0;
}

int RunGaitCommand(const GaitArgs& args) {
  if (!args.out_dir.empty()) {
    ipmc::CheckRunOutputDirectory("gait", "--out", args.out_dir,
                                  {args.model_path, args.csv_path});
  }
  ipmc::Simulation sim(ipmc::LoadModelFile(args.model_path), args.model_path);
  const std::unique_ptr<ipmc::Gait> gait = MakeGait(args, CountServos(sim.model()));
  std::optional<ipmc::DirectoryLock> hold;  // one run per output directory
  if (!args.out_dir.empty()) hold.emplace(args.out_dir);
  ipmc::RunWatch watch("gait", args.run.cycles * gait->Period_s());
  ipmc::GaitRunOptions options = args.run;
  options.on_sample = [&](double t_s) { watch.At(t_s); };
  const ipmc::GaitRunResult result = ipmc::RunGait(sim, *gait, options);
  watch.Finish();
  PrintGaitResult(result);
  if (!args.out_dir.empty()) {
    nlohmann::json inputs = {{"model", AbsolutePath(args.model_path)}, {"gait", args.gait},
                             {"frequency_Hz", args.frequency_Hz},
                             {"amplitude_rad", args.amplitude_rad},
                             {"phase_lag_rad", args.phase_lag_rad},
                             {"cycles", args.run.cycles}, {"csv", args.csv_path}};
    ipmc::WriteGaitOutputs(args.out_dir, result, inputs);
    PrintWritten(args.out_dir);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ipmc-swim: an IPMC flagellum swimming in Stokes flow (MuJoCo 2.2)"};
  app.set_version_flag("--version", std::string("ipmc-swim ") + ipmc::ProgramVersion());
  app.require_subcommand(1);
  GenerateArgs generate;
  GaitArgs gait;
  AddGenerateCommand(app, generate);
  AddGaitCommand(app, gait);
  BenchArgs bench;
  AddBenchCommand(app, bench);
  RunArgs run;
  AddRunCommand(app, run);
  ipmc::AnalysisArgs analysis;
  ipmc::AddAnalysisCommands(app, analysis);
  ipmc::RenderArgs render;
  ipmc::AddRenderCommand(app, render);
  ipmc::PlotArgs plot;
  ipmc::AddPlotCommand(app, plot);
  ipmc::IdentifyArgs identify;
  ipmc::AddIdentifyCommands(app, identify);
  ipmc::SweepArgs sweep;
  ipmc::AddSweepCommands(app, sweep);
  ipmc::Table5Args table5;
  ipmc::AddTable5Command(app, table5);
  ipmc::KeysArgs keys;
  ipmc::AddKeysCommand(app, keys);
  std::string commands;
  bool known = false;
  for (const CLI::App* command : app.get_subcommands({})) {
    commands += (commands.empty() ? "" : ", ") + command->get_name();
    known = known || (argc > 1 && command->get_name() == argv[1]);
  }
  if (argc > 1 && argv[1][0] != '-' && !known) {
    std::cerr << "ipmc-swim: error: unknown command '" << argv[1] << "' (commands: " << commands
              << ")\n";
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ipmc-swim: error: " << e.what() << " (see --help)\n";
    return 2;
  }
  mju_user_warning = CollectMujocoWarning;
  try {
    int status = 0;
    if (app.got_subcommand("generate")) status = RunGenerate(generate);
    if (app.got_subcommand("gait")) status = RunGaitCommand(gait);
    if (app.got_subcommand("bench")) status = RunBenchCommand(bench);
    if (app.got_subcommand("run")) status = RunScenarioCommand(run);
    if (int s = ipmc::RunAnalysisCommand(app, analysis); s >= 0) status = s;
    if (int s = ipmc::RunRenderCommand(app, render); s >= 0) status = s;
    if (int s = ipmc::RunPlotCommand(app, plot); s >= 0) status = s;
    if (int s = ipmc::RunIdentifyCommand(app, identify); s >= 0) status = s;
    if (int s = ipmc::RunSweepCommand(app, sweep); s >= 0) status = s;
    if (int s = ipmc::RunTable5Command(app, table5); s >= 0) status = s;
    if (int s = ipmc::RunKeysCommand(app, keys); s >= 0) status = s;
    PrintMujocoWarnings();
    return status;
  } catch (const ipmc::Interrupted& stop) {
    std::cerr << "ipmc-swim: interrupted by " << stop.SignalName() << ": " << stop.what() << "\n";
    return stop.ExitCode();
  } catch (const std::exception& e) {
    std::cerr << "ipmc-swim: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
