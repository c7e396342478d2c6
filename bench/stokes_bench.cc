// The Stokes-flow stepper (plugin/dynamics/stokes_step.h, docs/DYNAMICS.md)
// against the inertial step and against bare MuJoCo, in one run:
//  - one 100 s cycle of the paper's closed-loop run (scenarios/paper.toml)
//    with dynamics = stokes at the 1 kHz controller sample, against bare
//    mj_step (MuJoCo's Euler, no callbacks) of the same model at 0.5 ms for
//    the same 100 s, and against the inertial run at its 0.5 ms;
//  - the same cycle with c1 = 150 um/mm and n = 1, 2, 4, 8, 16, 31 rigid
//    sub-segments per link (31: the nesting limit with the head), Stokes at
//    1 ms (the same step for every n), and inertial at 0.5 ms for n = 1, 2
//    (n = 4 diverges at 0.5 ms); n = 1 and 16 three times (medians);
//  - the Stokes step alone against the number of hinges (3 to 96) on the
//    clamped flagellum, 3 V sines, counter step_hinge: the time per step
//    and hinge, flat if the cost is linear in the number of segments;
//  - one 100 s cycle of that clamped flagellum at 1 and 32 sub-segments
//    per link (96 hinges: 32 per link fit the nesting limit without the
//    head).
// Ratios at the end: CPU time relative to BM_BareEuler, and the sub-segment
// rows relative to the rigid Stokes row.
//
//   ./build/bench/stokes_bench
//   ./build/bench/stokes_bench --benchmark_filter=StepPerHinge
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "bench/ratio_reporter.h"
#include "sim/core/data_paths.h"
#include "ipmc_swim/fields.h"
#include "ipmc_swim/ipmc_swim.h"
#include "sim/core/model_generator.h"
#include "sim/core/scenario.h"
#include "sim/core/simulation.h"
#include "sim/base/numbers.h"
#include "sim/io/mjcf_edit.h"
#include "sim/runs/closed_loop_run.h"

namespace ipmc {
namespace {

const std::string kPaperScenario = ScenariosDir() + "/paper.toml";

ScenarioConfig PaperCycle(Dynamics dynamics, double timestep_s, int segments, double c1) {
  ScenarioConfig scenario = LoadScenario(kPaperScenario);
  scenario.run.cycles = 1;
  scenario.model.dynamics = dynamics;
  scenario.run.timestep_s = timestep_s;
  if (segments > 0) scenario.model.segments_per_link = segments;
  if (c1 > 0) scenario.waveform.c1_um_per_mm = c1;
  return scenario;
}

void BM_PaperCycleStokes(benchmark::State& state) {
  const ScenarioConfig scenario = PaperCycle(Dynamics::kStokes, 1e-3, 0, 0);
  for (auto _ : state) benchmark::DoNotOptimize(SimulateScenario(scenario));
}
void BM_PaperCycleInertial(benchmark::State& state) {
  const ScenarioConfig scenario = PaperCycle(Dynamics::kInertial, 5e-4, 0, 0);
  for (auto _ : state) benchmark::DoNotOptimize(SimulateScenario(scenario));
}
// Bare mj_step (Euler, no callbacks) of the paper's model, 100 s at 0.5 ms.
void BM_BareEuler(benchmark::State& state) {
  const ScenarioConfig scenario = PaperCycle(Dynamics::kInertial, 5e-4, 0, 0);
  std::string source;
  ModelPtr m = LoadScenarioModel(scenario, &source);
  m->opt.integrator = mjINT_EULER;
  DataPtr d(mj_makeData(m.get()));
  const mjfGeneric passive = mjcb_passive, control = mjcb_control;
  mjcb_passive = nullptr;
  mjcb_control = nullptr;
  const long steps = std::lround(100.0 / 5e-4);
  for (auto _ : state) {
    mj_resetData(m.get(), d.get());
    for (long i = 0; i < steps; ++i) {
      for (int a = 0; a < m->nu; ++a) d->ctrl[a] = 1e-5 * std::sin(kTwoPi * d->time + a);
      mj_step(m.get(), d.get());
    }
  }
  mjcb_passive = passive;
  mjcb_control = control;
}
void BM_SegmentsStokes(benchmark::State& state) {
  const ScenarioConfig scenario =
      PaperCycle(Dynamics::kStokes, 1e-3, static_cast<int>(state.range(0)), 150);
  for (auto _ : state) benchmark::DoNotOptimize(SimulateScenario(scenario));
}
void BM_SegmentsInertial(benchmark::State& state) {
  const ScenarioConfig scenario =
      PaperCycle(Dynamics::kInertial, 5e-4, static_cast<int>(state.range(0)), 150);
  for (auto _ : state) benchmark::DoNotOptimize(SimulateScenario(scenario));
}

// `steps` Stokes steps of 1 ms of the clamped flagellum (no head, so 32
// sub-segments per link fit MuJoCo's nesting limit) with n sub-segments
// per link, voltages 3 sin(2 pi t - q pi / 4) new every step.
void StepClamped(int segments_per_link, long steps) {
  FlagellumSpec spec;
  spec.clamped = true;
  spec.head_length_mm = 0;
  spec.segments_per_link = segments_per_link;
  spec.timestep_s = 1e-3;
  spec.integrator = "Euler";
  const std::string xml =
      SetMjcfCustomField(GenerateFlagellumMjcf(spec), "text", kAttrDynamics, "stokes");
  Simulation sim(LoadModelString(xml), "clamped flagellum");
  std::vector<double> volts(3);
  for (long i = 0; i < steps; ++i) {
    for (int q = 0; q < 3; ++q) volts[q] = 3.0 * std::sin(kTwoPi * sim.data()->time - 0.785 * q);
    SetVoltages(sim.data(), volts.data(), 3);
    sim.Step(false);
  }
}

// 10 000 steps: the cost per step and hinge.
void BM_StepPerHinge(benchmark::State& state) {
  const long steps = 10000;
  const int hinges = 3 * static_cast<int>(state.range(0));
  for (auto _ : state) StepClamped(static_cast<int>(state.range(0)), steps);
  const auto per_item = benchmark::Counter::kIsRate | benchmark::Counter::kInvert;
  const double total = static_cast<double>(steps) * state.iterations();
  state.counters["step"] = benchmark::Counter(total, per_item);
  state.counters["step_hinge"] = benchmark::Counter(total * hinges, per_item);
}

// One 100 s cycle (100 000 steps) of the clamped flagellum.
void BM_ClampedCycle(benchmark::State& state) {
  for (auto _ : state) StepClamped(static_cast<int>(state.range(0)), 100000);
}

void Long(benchmark::internal::Benchmark* b) {
  b->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(3)->ReportAggregatesOnly(true);
}
void Once(benchmark::internal::Benchmark* b) {
  b->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(1);
}

BENCHMARK(BM_PaperCycleStokes)->Apply(Long);
BENCHMARK(BM_PaperCycleInertial)->Apply(Long);
BENCHMARK(BM_BareEuler)->Apply(Long);
// n = 1 and 16 (the cost target's pair) medians of 3, the others once.
BENCHMARK(BM_SegmentsStokes)->Arg(1)->Arg(16)->Apply(Long);
BENCHMARK(BM_SegmentsStokes)->Arg(2)->Arg(4)->Arg(8)->Arg(31)->Apply(Once);
BENCHMARK(BM_SegmentsInertial)->Arg(1)->Arg(2)->Apply(Once);
BENCHMARK(BM_StepPerHinge)->Arg(1)->Arg(2)->Arg(4)->Arg(8)->Arg(16)->Arg(32)->Apply(Long);
BENCHMARK(BM_ClampedCycle)->Arg(1)->Arg(32)->Apply(Once);

}  // namespace
}  // namespace ipmc

int main(int argc, char** argv) {
  return ipmc::RunWithRatios(argc, argv, {"BM_BareEuler", "BM_SegmentsStokes/1"},
                             {{"BM_PaperCycleStokes", "BM_PaperCycleInertial"},
                              {"BM_SegmentsStokes/16", "BM_SegmentsStokes/1"},
                              {"BM_SegmentsStokes/31", "BM_SegmentsStokes/1"}},
                             ipmc::RatioClock::kCpu);
}
