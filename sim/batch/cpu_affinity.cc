#include "sim/batch/cpu_affinity.h"

#include <sched.h>

#include <algorithm>
#include <cerrno>
#include <thread>

namespace ipmc {

int AvailableCpus() {
  // The kernel's mask may be wider than cpu_set_t's 1024 CPUs: grow the
  // set until sched_getaffinity accepts it.
  constexpr int kMaxCpus = 1 << 20;
  for (int cpus = 1024; cpus <= kMaxCpus; cpus *= 2) {
    cpu_set_t* set = CPU_ALLOC(cpus);
    if (set == nullptr) break;
    const size_t size = CPU_ALLOC_SIZE(cpus);
    CPU_ZERO_S(size, set);
    const int result = sched_getaffinity(0, size, set);
    const int error = errno;
    const int count = result == 0 ? CPU_COUNT_S(size, set) : 0;
    CPU_FREE(set);
    if (result == 0 && count > 0) return count;
    if (result != 0 && error != EINVAL) break;
  }
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

}  // namespace ipmc
