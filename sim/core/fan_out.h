// Independent tasks on a few threads, for sweeps, the two Table 5 runs
// and the identification pipeline's bench runs. Each task must own what
// it writes (its own Simulation, its own result slot); the MuJoCo warning
// hook is serialised while more than one thread runs
// (sim/core/mujoco_warnings.h).
#pragma once

#include <cstddef>
#include <functional>

namespace ipmc {

// Runs task(0) .. task(count - 1), handed out in index order to
// min(threads, count) threads (the calling thread alone when that is 1).
// After a task throws, no further task starts; when the running ones have
// finished, the exception of the failed task with the lowest index is
// rethrown. Throws std::invalid_argument if threads < 1.
void FanOut(std::size_t count, int threads, const std::function<void(std::size_t)>& task);

}  // namespace ipmc
