#include "sim/core/fan_out.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "sim/core/mujoco_warnings.h"

namespace ipmc {

void FanOut(std::size_t count, int threads, const std::function<void(std::size_t)>& task) {
  if (threads < 1) {
    throw std::invalid_argument("FanOut: threads must be >= 1, got " + std::to_string(threads));
  }
  std::vector<std::exception_ptr> failures(count);
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  const auto work = [&] {
    while (!failed) {
      const std::size_t i = next++;
      if (i >= count) return;
      try {
        task(i);
      } catch (...) {
        failures[i] = std::current_exception();
        failed = true;
      }
    }
  };
  const std::size_t used = std::min<std::size_t>(static_cast<std::size_t>(threads), count);
  if (used <= 1) {
    work();
  } else {
    const SerialisedMujocoWarnings warnings;
    std::vector<std::thread> pool;
    for (std::size_t t = 0; t < used; ++t) pool.emplace_back(work);
    for (std::thread& thread : pool) thread.join();
  }
  for (const std::exception_ptr& failure : failures) {
    if (failure) std::rethrow_exception(failure);
  }
}

}  // namespace ipmc
