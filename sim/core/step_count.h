// The number of fixed time steps an interval takes, checked: a run whose
// step count rounds to zero, or is too large to finish, would otherwise
// "succeed" with empty or never-ending output.
#pragma once

#include <string>

namespace ipmc {

// Most steps one interval (a wave cycle, a bench experiment) may take: a
// count no machine runs (the practical limit is CheckRunSize's).
constexpr double kMaxStepsPerInterval = 1e15;

// Fewest samples of one wave cycle (controller samples in a closed-loop
// run, physics steps in a gait run): a wave read at fewer points is not
// one the body can follow (at two, a sine is read at its zeros and the
// run moves nothing).
constexpr long kMinSamplesPerWaveCycle = 10;

// round(interval_s / timestep_s), at least `min_steps`. Throws
// std::invalid_argument naming `what` (e.g. "scenario.toml: one wave cycle")
// when the time step is not finite and > 0, the interval is not finite and
// > 0, or the count is outside [min_steps, kMaxStepsPerInterval].
long CheckedStepCount(double interval_s, double timestep_s, long min_steps, const std::string& what);

// Most physics steps, and bytes of recorded samples, one run may take
// unless the user allows more (`--allow-long`): 1e8 coupled steps take
// about 10 min at kMeasuredStepCost_s, and a run's samples stay in memory.
constexpr double kMaxRunSteps = 1e8;
constexpr double kMaxRunRecordBytes = 2e9;
// One coupled step of the three-link paper model [s], as closed_loop_bench
// measures it on a 2-core laptop-class machine; for estimates only.
constexpr double kMeasuredStepCost_s = 6e-6;

// Throws std::invalid_argument naming `what` ("scenario.toml: the run")
// with the estimate (steps, wall time at kMeasuredStepCost_s, memory of
// the recorded samples) if the run exceeds either limit and is not
// `allowed`. Throws anyway for more than 1e15 steps or 1e15 bytes, which
// no machine runs or holds.
void CheckRunSize(double steps, double recorded_bytes, bool allowed, const std::string& what);

// A dense Stokeslet model of N points (plugin/fluid/fluid_model.h) holds a
// 3N x 3N mobility matrix and its Cholesky factor (16 (3N)^2 bytes) and
// factors it, (3N)^3 / 3 flops, each time the resistance is recomputed
// (up to every step). kStokesletFlops: what one core of the 2-core machine
// factors per second at 3N = 1200-2400 (Eigen's LLT; for estimates only).
constexpr double kStokesletFlops = 1e9;
// Most seconds one recomputation may take unless the user allows more:
// a run recomputes tens of times a cycle.
constexpr double kMaxStokesletRecompute_s = 30.0;

// Throws std::invalid_argument "WHAT: N Stokeslet points make a ... matrix
// of B (its factor included) and take about T to factor ..." if the
// matrices exceed kMaxRunRecordBytes (whatever `allowed`), or one
// recomputation exceeds kMaxStokesletRecompute_s and the run is not
// `allowed` (--allow-long). `points` is a double: a count no int holds is
// refused, not wrapped.
void CheckStokesletSize(double points, bool allowed, const std::string& what);

// Memory of one recorded sample of a run [bytes], roughly: the state (nq
// positions), the pose, and a few values per link.
inline double RecordedSampleBytes(int nq, int links) {
  constexpr double kPoseValues = 16;
  constexpr double kValuesPerLink = 3;
  constexpr double kVectorOverhead = 4 * 24;
  return (nq + kPoseValues + kValuesPerLink * links) * sizeof(double) + kVectorOverhead;
}

}  // namespace ipmc
