// The project's serial vector kernels (plugin/actuators/serial_kernels.h) against
// Debian's stock N_V*_Serial ones, both called through the vector's
// operation table as CVODE calls them, on the bank's 30 states (3 paper
// links) and on 300.
//
//   ./build/bench/serial_kernels_bench
#include <benchmark/benchmark.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

#include "plugin/actuators/serial_kernels.h"

namespace ipmc {
namespace {

struct Vectors {
  explicit Vectors(sunindextype n, bool project_kernels) {
    SUNContext_Create(nullptr, &context);
    x = N_VNew_Serial(n, context);
    if (project_kernels) serial_kernels::Install(x);
    y = N_VClone(x);
    z = N_VClone(x);
    for (sunindextype i = 0; i < n; ++i) {
      NV_Ith_S(x, i) = 0.1 * static_cast<double>(i) - 1.0;
      NV_Ith_S(y, i) = 1.0 / static_cast<double>(i + 1);
    }
  }
  ~Vectors() {
    N_VDestroy(x);
    N_VDestroy(y);
    N_VDestroy(z);
    SUNContext_Free(&context);
  }
  SUNContext context = nullptr;
  N_Vector x, y, z;
};

void LinearSum(benchmark::State& state, bool project_kernels) {
  Vectors v(state.range(0), project_kernels);
  for (auto _ : state) {
    N_VLinearSum(0.3, v.x, 0.7, v.y, v.z);
    benchmark::DoNotOptimize(NV_DATA_S(v.z));
    benchmark::ClobberMemory();
  }
}

void WrmsNorm(benchmark::State& state, bool project_kernels) {
  Vectors v(state.range(0), project_kernels);
  for (auto _ : state) benchmark::DoNotOptimize(N_VWrmsNorm(v.x, v.y));
}

void Scale(benchmark::State& state, bool project_kernels) {
  Vectors v(state.range(0), project_kernels);
  for (auto _ : state) {
    N_VScale(0.3, v.x, v.z);
    benchmark::DoNotOptimize(NV_DATA_S(v.z));
    benchmark::ClobberMemory();
  }
}

BENCHMARK_CAPTURE(LinearSum, stock, false)->Arg(30)->Arg(300);
BENCHMARK_CAPTURE(LinearSum, project, true)->Arg(30)->Arg(300);
BENCHMARK_CAPTURE(WrmsNorm, stock, false)->Arg(30)->Arg(300);
BENCHMARK_CAPTURE(WrmsNorm, project, true)->Arg(30)->Arg(300);
BENCHMARK_CAPTURE(Scale, stock, false)->Arg(30)->Arg(300);
BENCHMARK_CAPTURE(Scale, project, true)->Arg(30)->Arg(300);

}  // namespace
}  // namespace ipmc

BENCHMARK_MAIN();
