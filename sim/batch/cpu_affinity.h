// The number of CPUs this process may run on: its affinity mask
// (sched_getaffinity), which `taskset`, cgroup cpusets and batch
// schedulers narrow, rather than the machine's core count.
#pragma once

namespace ipmc {

// CPUs in the calling thread's affinity mask (>= 1); the hardware thread
// count if the mask cannot be read.
int AvailableCpus();

}  // namespace ipmc
