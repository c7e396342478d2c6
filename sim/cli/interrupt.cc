#include "sim/cli/interrupt.h"

#include <pthread.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <utility>

namespace ipmc {
namespace {

// How often the watcher looks whether it should end [ns].
constexpr long kPollInterval_ns = 100'000'000;
// The shell's exit code for a process ended by SIGINT (128 + 2).
constexpr int kInterruptedExitCode = 130;

sigset_t InterruptSet() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  return set;
}

}  // namespace

InterruptAtBoundary::InterruptAtBoundary(std::string message) : message_(std::move(message)) {
  const sigset_t set = InterruptSet();
  pthread_sigmask(SIG_BLOCK, &set, &previous_mask_);
  watcher_ = std::thread([this] { Watch(); });
}

InterruptAtBoundary::~InterruptAtBoundary() {
  finished_ = true;
  watcher_.join();
  // A SIGINT still pending is delivered now, with its default action.
  pthread_sigmask(SIG_SETMASK, &previous_mask_, nullptr);
}

void InterruptAtBoundary::Watch() {
  const sigset_t set = InterruptSet();
  const timespec interval = {0, kPollInterval_ns};
  while (!finished_) {
    if (sigtimedwait(&set, nullptr, &interval) != SIGINT) continue;  // timeout or EINTR
    if (requested_) {
      std::fputs("\ninterrupted again: stopping now\n", stderr);
      std::_Exit(kInterruptedExitCode);
    }
    requested_ = true;
    std::fprintf(stderr, "\n%s\n", message_.c_str());
  }
}

}  // namespace ipmc
