// Frames per second of 640x480 off-screen rendering of the swimming
// flagellum, alone and with H.264 encoding through ffmpeg, in one run.
// The swimmer moves between frames (hinges swinging under their own
// stiffness, drag on), so the trail and the camera do real work.
//
// And the cost of filming a run: one cycle (100 s, 2e5 steps) of the
// paper's closed-loop scenario (scenarios/paper.toml) run alone, and run
// and filmed at 25 frames per wave cycle (simulation, rendering and
// encoding of the default 640x480 film: fixed camera, grid, ghost,
// trails); the ratio of the two wall times is the filming overhead.
//
//   ./build/bench/render_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cstdio>
#include <string>
#include <vector>

#include "bench/ratio_reporter.h"
#include "sim/core/data_paths.h"
#include "renders/offscreen_renderer.h"
#include "renders/swim_film.h"
#include "renders/video.h"
#include "sim/core/model_generator.h"
#include "sim/core/scenario.h"
#include "sim/core/simulation.h"

namespace ipmc {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;
constexpr int kStepsPerFrame = 40;

// Advances the bent flagellum between frames, re-bending it every 100 frames.
void AdvanceSwimmer(Simulation& sim, long frame) {
  mjData* d = sim.data();
  if (frame % 100 == 0) {
    mj_resetData(sim.model(), d);
    for (int i = sim.model()->nq - 3; i < sim.model()->nq; ++i) d->qpos[i] = 0.4;
  }
  for (int i = 0; i < kStepsPerFrame; ++i) sim.Step();
}

void BM_Render640x480(benchmark::State& state) {
  Simulation sim(LoadModelString(GenerateFlagellumMjcf(FlagellumSpec())), "flagellum");
  OffscreenRenderer renderer(sim.model(), kWidth, kHeight);
  long frames = 0;
  for (auto _ : state) {
    state.PauseTiming();
    AdvanceSwimmer(sim, frames);
    state.ResumeTiming();
    benchmark::DoNotOptimize(renderer.Frame(sim.data()));
    ++frames;
  }
  state.counters["frames_per_second"] = benchmark::Counter(frames, benchmark::Counter::kIsRate);
}

void BM_Render640x480WithEncoding(benchmark::State& state) {
  Simulation sim(LoadModelString(GenerateFlagellumMjcf(FlagellumSpec())), "flagellum");
  OffscreenRenderer renderer(sim.model(), kWidth, kHeight);
  const std::string path = "/tmp/ipmc_render_bench.mp4";
  Mp4Writer video(path, kWidth, kHeight, 25.0);
  long frames = 0;
  for (auto _ : state) {
    state.PauseTiming();
    AdvanceSwimmer(sim, frames);
    state.ResumeTiming();
    video.AddFrame(renderer.Frame(sim.data()));
    ++frames;
  }
  video.Finish();
  std::remove(path.c_str());
  state.counters["frames_per_second"] = benchmark::Counter(frames, benchmark::Counter::kIsRate);
}

ScenarioConfig PaperCycle() {
  ScenarioConfig scenario = LoadScenario(ScenariosDir() + "/paper.toml");
  scenario.run.cycles = 1;
  scenario.output.dir.clear();
  return scenario;
}

void BM_PaperRun(benchmark::State& state) {
  const ScenarioConfig scenario = PaperCycle();
  for (auto _ : state) benchmark::DoNotOptimize(SimulateScenario(scenario));
}

void BM_PaperRunFilmed(benchmark::State& state) {
  const ScenarioConfig scenario = PaperCycle();
  FilmConfig film;
  film.frames_per_cycle = 25;
  const std::string path = "/tmp/ipmc_render_bench_film.mp4";
  for (auto _ : state) benchmark::DoNotOptimize(SimulateAndFilmScenario(scenario, film, path));
  std::remove(path.c_str());
}

BENCHMARK(BM_Render640x480)->MinTime(3.0)->UseRealTime();
BENCHMARK(BM_Render640x480WithEncoding)->MinTime(3.0)->UseRealTime();
BENCHMARK(BM_PaperRun)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK(BM_PaperRunFilmed)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace
}  // namespace ipmc

int main(int argc, char** argv) {
  return ipmc::RunWithRatios(argc, argv, std::vector<std::string>{"BM_Render640x480", "BM_PaperRun"});
}
