#include "sim/runs/bench_command.h"

#include "sim/core/data_paths.h"
#include "sim/base/error.h"
#include "sim/io/files.h"

namespace ipmc {
namespace {

constexpr char kCommand[] = "bench";

OptionTable<BenchCommand> MakeBenchOptions() {
  OptionTable<BenchCommand> table(
      kCommand, "Voltage experiment on the test bench, recorded like the laser meter");
  OptionInfo model{"model", "", "an MJCF file with IPMC actuators", "The model"};
  model.default_text = "models/flagellum3_clamped.xml";
  table.AddPath(model,
                [](BenchCommand& c) -> std::string& { return c.model; });
  OptionInfo signal{"signal", "", "", "sine: A sin(2 pi f t) | chirp: linear sweep f0 to f1"};
  signal.choices = {"sine", "chirp"};
  table.Add<std::string>(signal, [](BenchCommand& c) -> std::string& { return c.signal; });
  table.Add<double>({"amplitude_V", "V", "finite, nonzero, within +-100", "Voltage amplitude A"},
                    [](BenchCommand& c) -> double& { return c.bench.amplitude_V; });
  table.Add<double>({"frequency_Hz", "Hz", "finite and > 0", "Sine frequency f"},
                    [](BenchCommand& c) -> double& { return c.bench.frequency_Hz; });
  OptionInfo start{"start_Hz", "Hz", "finite and > 0", "Chirp start frequency f0"};
  start.aliases = {"f0_Hz"};
  table.Add<double>(start, [](BenchCommand& c) -> double& { return c.bench.start_Hz; });
  OptionInfo end{"end_Hz", "Hz", "above start_Hz, below half sample_rate_Hz",
                 "Chirp end frequency f1"};
  end.aliases = {"f1_Hz"};
  table.Add<double>(end, [](BenchCommand& c) -> double& { return c.bench.end_Hz; });
  table.Add<double>({"duration_s", "s", "finite and > 0", "Duration T"},
                    [](BenchCommand& c) -> double& { return c.bench.duration_s; });
  OptionInfo links{"links", "", "distinct links of the model, 1-based", "Driven links"};
  links.aliases = {"driven_links"};
  table.Add<std::vector<int>>(links,
                              [](BenchCommand& c) -> std::vector<int>& { return c.bench.driven_links; });
  table.Add<double>({"sample_rate_Hz", "Hz", "a whole number of time steps per sample",
                     "Voltage update and recording rate"},
                    [](BenchCommand& c) -> double& { return c.bench.sample_rate_Hz; });
  table.Add<bool>({"allow_long", "", "",
                   "Run even beyond 1e8 steps or 2 GB of recorded samples (refused otherwise, "
                   "with the estimate)"},
                  [](BenchCommand& c) -> bool& { return c.bench.allow_long; });
  OptionInfo out{"out", "", "a file, not the model", "CSV file to write"};
  out.aliases = {"o"};
  table.AddPath(out, [](BenchCommand& c) -> std::string& { return c.out; });
  return table;
}

}  // namespace

BenchCommand::BenchCommand() : model(ModelsDir() + "/flagellum3_clamped.xml") {}

const OptionTable<BenchCommand>& BenchOptions() {
  static const OptionTable<BenchCommand> table = MakeBenchOptions();
  return table;
}

BenchRecord RunBenchCommand(const BenchCommand& command, const BenchProgress& progress) {
  if (command.signal != "sine" && command.signal != "chirp") {
    ThrowOption(kCommand, "signal", "sine or chirp", "'" + command.signal + "'");
  }
  BenchSignal signal = command.bench;
  signal.kind = command.signal == "chirp" ? BenchSignal::Kind::kChirp : BenchSignal::Kind::kSine;
  signal.Validate();
  if (!command.out.empty()) {
    try {
      RefuseOverwritingInputs(kCommand, "out", command.out, {command.model});
    } catch (const std::invalid_argument& error) {
      throw FieldError(error.what(), "out", "not the model");
    }
    RequireWritableParent(command.out);
  }
  Simulation sim(LoadModelFile(command.model), command.model);
  const BenchRecord record = RunBench(sim, signal, 0.0, progress);
  if (!command.out.empty()) WriteFileAtomically(command.out, BenchCsv(record));
  return record;
}

}  // namespace ipmc
