// The coupled step against MuJoCo's own, in one run (so that the ratios
// hold on a loaded machine):
//  - the paper's closed-loop run (scenarios/paper.toml: 300 s, 600 000
//    steps of 0.5 ms with controllers, references, swim meter and
//    recording) against bare mj_step of the same model for the same steps
//    (no callbacks) with the integrator the run uses (MuJoCo's Euler, as
//    the coupling's step chooses it) and with the model file's implicit,
//    and against the same model coupled with the drag alone,
//    with the IPMC actuators alone and with both (a 3 V sine per link, new
//    voltages every 1 ms as from the controllers);
//  - the paper's bench chirp (3 V, 0.1-200 Hz, 200 s on
//    models/flagellum3_clamped.xml, recorded at 1 kHz as `ipmc-swim bench`
//    records it);
//  - a step against the number of links (3, 6, 12, 24 links of 10 mm,
//    0.5 ms step) and of rigid sub-segments per link (1, 2, 4, 8 on three
//    links, at the 7.8 us step that 8 need), coupled and bare: counters
//    step and step_link, the time per step and per step and link (or
//    hinge, for the sub-segments);
//  - first of all, the peak memory of a 20 s and of a 2000 s closed-loop
//    run (the paper's scenario at 0.05 Hz, 1 and 100 cycles, one recorded
//    sample per cycle), each in a child process started before any
//    benchmark; --skip_memory leaves it out.
// At the end each benchmark's median CPU time (one thread each, so steadier
// than wall time on a shared machine) is printed relative to the bare
// Euler step of the paper's model and, for the scaling rows, to the bare
// step of the same model.
//
//   ./build/bench/closed_loop_bench
//   ./build/bench/closed_loop_bench --skip_memory --benchmark_filter=Links
#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bench/ratio_reporter.h"
#include "sim/core/data_paths.h"
#include "ipmc_swim/ipmc_swim.h"
#include "sim/core/model_generator.h"
#include "sim/core/scenario.h"
#include "sim/core/simulation.h"
#include "sim/base/numbers.h"
#include "sim/runs/bench_run.h"
#include "sim/runs/closed_loop_run.h"

namespace ipmc {
namespace {

const std::string kPaperScenario = ScenariosDir() + "/paper.toml";
const std::string kClampedModel = ModelsDir() + "/flagellum3_clamped.xml";

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// `xml` without the <custom> lines that declare a field whose name starts
// with `prefix` (the drag asks for all its ipmc_rft_ fields or none).
std::string WithoutField(std::string xml, const std::string& prefix) {
  for (size_t at; (at = xml.find("name=\"" + prefix)) != std::string::npos;) {
    const size_t begin = xml.rfind('\n', at) + 1;
    const size_t end = xml.find('\n', at) + 1;
    xml = xml.substr(0, begin) + xml.substr(end);
  }
  return xml;
}

// The paper scenario's model file, step and number of steps.
struct PaperSetting {
  std::string xml;
  double timestep_s;
  long steps;
};

const PaperSetting& Paper() {
  static const PaperSetting setting = [] {
    const ScenarioConfig scenario = LoadScenario(kPaperScenario);
    const double timestep_s = scenario.run.timestep_s.value_or(5e-4);
    const double duration_s = scenario.run.cycles / std::abs(scenario.waveform.frequency_Hz);
    return PaperSetting{ReadText(scenario.model.path), timestep_s,
                        std::lround(duration_s / timestep_s)};
  }();
  return setting;
}

// MuJoCo's callbacks switched off for the lifetime of the object.
class CallbacksOff {
 public:
  CallbacksOff() : passive_(mjcb_passive), control_(mjcb_control) {
    mjcb_passive = nullptr;
    mjcb_control = nullptr;
  }
  ~CallbacksOff() {
    mjcb_passive = passive_;
    mjcb_control = control_;
  }

 private:
  mjfGeneric passive_, control_;
};

// Time per step, and per step and link (or hinge).
void CountSteps(benchmark::State& state, long steps, int per) {
  const double total = static_cast<double>(steps) * state.iterations();
  const auto per_item = benchmark::Counter::kIsRate | benchmark::Counter::kInvert;
  state.counters["step"] = benchmark::Counter(total, per_item);
  state.counters["step_link"] = benchmark::Counter(total * per, per_item);
}

// A slow sine on every motor, so that a body without IPMC actuators moves.
void DriveMotors(const mjModel* m, mjData* d) {
  for (int a = 0; a < m->nu; ++a) d->ctrl[a] = 1e-5 * std::sin(kTwoPi * d->time + a);
}

// `steps` steps of `xml` at `timestep_s`, no callbacks, with `integrator`
// (MuJoCo's Euler is what the coupling steps these models with: they have
// no velocity gains, tendon damping or MuJoCo fluid, docs/LIBRARY.md).
void BareSteps(benchmark::State& state, const std::string& xml, double timestep_s, long steps,
               int integrator, int per) {
  ModelPtr m = LoadModelString(xml);
  m->opt.timestep = timestep_s;
  m->opt.integrator = integrator;
  DataPtr d(mj_makeData(m.get()));
  const CallbacksOff off;
  for (auto _ : state) {
    mj_resetData(m.get(), d.get());
    for (long i = 0; i < steps; ++i) {
      DriveMotors(m.get(), d.get());
      mj_step(m.get(), d.get());
    }
  }
  CountSteps(state, steps, per);
}

// `steps` coupled steps of `xml` at `timestep_s`. With `links` > 0 each
// link's voltage is 3 sin(2 pi t - q pi / 4) [V], new every 1 ms; with 0
// (no IPMC actuators) the motors get DriveMotors' sine. The integrator is
// the one the runs use.
void CoupledSteps(benchmark::State& state, const std::string& xml, double timestep_s, long steps,
                  int links, int per) {
  const long steps_per_voltage = std::max(1L, std::lround(1e-3 / timestep_s));
  std::vector<double> volts(std::max(links, 1), 0.0);
  for (auto _ : state) {
    ModelPtr m = LoadModelString(xml);
    m->opt.timestep = timestep_s;
    Simulation sim(std::move(m), "benchmark model");
    const mjModel* model = sim.model();
    mjData* d = sim.data();
    for (long i = 0; i < steps; ++i) {
      if (links == 0) {
        DriveMotors(model, d);
      } else if (i % steps_per_voltage == 0) {
        for (int q = 0; q < links; ++q) volts[q] = 3.0 * std::sin(kTwoPi * d->time - 0.785 * q);
        SetVoltages(d, volts.data(), links);
      }
      if (!Step(model, d)) throw std::runtime_error(LastError(d));
    }
  }
  CountSteps(state, steps, per);
}

// The paper's run and its floors, all over the same steps.
void BM_PaperRun(benchmark::State& state) {
  const ScenarioConfig scenario = LoadScenario(kPaperScenario);
  for (auto _ : state) benchmark::DoNotOptimize(SimulateScenario(scenario));
  CountSteps(state, Paper().steps, 3);
}
void BM_BareEuler(benchmark::State& state) {
  BareSteps(state, Paper().xml, Paper().timestep_s, Paper().steps, mjINT_EULER, 3);
}
void BM_BareImplicit(benchmark::State& state) {
  BareSteps(state, Paper().xml, Paper().timestep_s, Paper().steps, mjINT_IMPLICIT, 3);
}
void BM_DragAlone(benchmark::State& state) {
  CoupledSteps(state, WithoutField(Paper().xml, "ipmc_links"), Paper().timestep_s, Paper().steps,
               0, 3);
}
void BM_ActuatorsAlone(benchmark::State& state) {
  CoupledSteps(state, WithoutField(Paper().xml, "ipmc_rft_"), Paper().timestep_s,
               Paper().steps, 3, 3);
}
void BM_DragAndActuators(benchmark::State& state) {
  CoupledSteps(state, Paper().xml, Paper().timestep_s, Paper().steps, 3, 3);
}

// `ipmc-swim bench --signal chirp`: 400 000 steps of the model file's 0.5 ms.
void BM_BenchChirp200s(benchmark::State& state) {
  BenchSignal chirp;
  chirp.kind = BenchSignal::Kind::kChirp;
  for (auto _ : state) {
    Simulation sim(LoadModelFile(kClampedModel), kClampedModel);
    benchmark::DoNotOptimize(RunBench(sim, chirp));
  }
}

// N links of 10 mm behind the 1 mm head, 0.5 ms step, 20 000 steps.
constexpr long kScalingSteps = 20000;
std::string LinksXml(int links) {
  FlagellumSpec spec;
  spec.link_lengths_mm.assign(links, 10.0);
  spec.timestep_s = 5e-4;
  return GenerateFlagellumMjcf(spec);
}
void BM_LinksCoupled(benchmark::State& state) {
  const int links = static_cast<int>(state.range(0));
  CoupledSteps(state, LinksXml(links), 5e-4, kScalingSteps, links, links);
}
void BM_LinksBare(benchmark::State& state) {
  const int links = static_cast<int>(state.range(0));
  BareSteps(state, LinksXml(links), 5e-4, kScalingSteps, mjINT_EULER, links);
}

// Three links of n sub-segments each, 20 000 steps of 5e-4 s / 8^2 (the
// hinge modes go as n^2, so n = 8 needs it; a simulated second costs n^2
// times more steps on top of the cost per step measured here).
constexpr double kSegmentsStep_s = 5e-4 / 64;
std::string SegmentsXml(int segments) {
  FlagellumSpec spec;
  spec.segments_per_link = segments;
  spec.timestep_s = kSegmentsStep_s;
  return GenerateFlagellumMjcf(spec);
}
void BM_SegmentsCoupled(benchmark::State& state) {
  const int segments = static_cast<int>(state.range(0));
  CoupledSteps(state, SegmentsXml(segments), kSegmentsStep_s, kScalingSteps, 3, 3 * segments);
}
void BM_SegmentsBare(benchmark::State& state) {
  const int segments = static_cast<int>(state.range(0));
  BareSteps(state, SegmentsXml(segments), kSegmentsStep_s, kScalingSteps, mjINT_EULER, 3 * segments);
}

void Long(benchmark::internal::Benchmark* b) {
  b->Iterations(1)->Repetitions(3)->ReportAggregatesOnly(true)->Unit(benchmark::kSecond);
}
void Short(benchmark::internal::Benchmark* b) {
  b->Repetitions(5)->ReportAggregatesOnly(true)->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_PaperRun)->Apply(Long);
BENCHMARK(BM_BareEuler)->Apply(Long);
BENCHMARK(BM_BareImplicit)->Apply(Long);
BENCHMARK(BM_DragAlone)->Apply(Long);
BENCHMARK(BM_ActuatorsAlone)->Apply(Long);
BENCHMARK(BM_DragAndActuators)->Apply(Long);
BENCHMARK(BM_BenchChirp200s)->Apply(Long);
BENCHMARK(BM_LinksCoupled)->Arg(3)->Arg(6)->Arg(12)->Arg(24)->Apply(Short);
BENCHMARK(BM_LinksBare)->Arg(3)->Arg(6)->Arg(12)->Arg(24)->Apply(Short);
BENCHMARK(BM_SegmentsCoupled)->Arg(1)->Arg(2)->Arg(4)->Arg(8)->Apply(Short);
BENCHMARK(BM_SegmentsBare)->Arg(1)->Arg(2)->Arg(4)->Arg(8)->Apply(Short);

// The peak resident memory [kB] of a child process that does `run`: each
// run starts from the same state of this process, before any benchmark.
long PeakMemoryOfChild_kB(void (*run)(int), int argument) {
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid == 0) {
    run(argument);
    _exit(0);
  }
  int status = 0;
  rusage usage{};
  if (pid < 0 || wait4(pid, &status, 0, &usage) != pid || !WIFEXITED(status)) return -1;
  return usage.ru_maxrss;
}

// The paper's scenario at 0.05 Hz (20 s cycles) for `cycles` cycles, one
// recorded sample per cycle.
void SimulatePaperScenarioFor(int cycles) {
  ScenarioConfig scenario = LoadScenario(kPaperScenario);
  scenario.waveform.frequency_Hz = 0.05;
  scenario.run.cycles = cycles;
  scenario.output.samples_per_cycle = 1;
  SimulateScenario(scenario);
}

void ReportMemoryGrowth() {
  const long short_kB = PeakMemoryOfChild_kB(SimulatePaperScenarioFor, 1);
  const long long_kB = PeakMemoryOfChild_kB(SimulatePaperScenarioFor, 100);
  std::printf("peak memory: %ld kB for a 20 s closed-loop run, %ld kB for a 2000 s one "
              "(ratio %.3f)\n\n",
              short_kB, long_kB, static_cast<double>(long_kB) / short_kB);
}

}  // namespace
}  // namespace ipmc

int main(int argc, char** argv) {
  std::vector<char*> args;
  bool memory = true;
  for (int i = 0; i < argc; ++i) {
    if (std::strcmp(argv[i], "--skip_memory") == 0) {
      memory = false;
    } else {
      args.push_back(argv[i]);
    }
  }
  if (memory) ipmc::ReportMemoryGrowth();
  int count = static_cast<int>(args.size());
  const std::vector<std::string> baselines = {"BM_BareEuler", "BM_BareImplicit"};
  const std::vector<std::pair<std::string, std::string>> pairs = {
      {"BM_LinksCoupled/3", "BM_LinksBare/3"},       {"BM_LinksCoupled/6", "BM_LinksBare/6"},
      {"BM_LinksCoupled/12", "BM_LinksBare/12"},     {"BM_LinksCoupled/24", "BM_LinksBare/24"},
      {"BM_SegmentsCoupled/1", "BM_SegmentsBare/1"}, {"BM_SegmentsCoupled/2", "BM_SegmentsBare/2"},
      {"BM_SegmentsCoupled/4", "BM_SegmentsBare/4"}, {"BM_SegmentsCoupled/8", "BM_SegmentsBare/8"}};
  return ipmc::RunWithRatios(count, args.data(), baselines, pairs, ipmc::RatioClock::kCpu);
}
