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
sigset_t InterruptSet() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);  // the terminal closed: as SIGTERM
  return set;
}

}  // namespace

int InterruptExitCode(int signal) { return 128 + (signal == SIGHUP ? SIGTERM : signal); }

int Interrupted::ExitCode() const { return InterruptExitCode(signal_); }

std::string Interrupted::SignalName() const {
  switch (signal_) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return std::to_string(signal_);
  }
}

void InterruptAtBoundary::ThrowIfRequested(const std::string& what) const {
  if (Requested()) throw Interrupted(signal_, what);
}

InterruptAtBoundary::InterruptAtBoundary(std::string message) : message_(std::move(message)) {
  const sigset_t set = InterruptSet();
  pthread_sigmask(SIG_BLOCK, &set, &previous_mask_);
  // A signal already pending (sent while it was blocked, before the work
  // began) requests the stop before the first safe point.
  const timespec no_wait = {0, 0};
  const int pending = sigtimedwait(&set, nullptr, &no_wait);
  if (pending == SIGINT || pending == SIGTERM || pending == SIGHUP) Take(pending);
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
    const int received = sigtimedwait(&set, nullptr, &interval);
    if (received != SIGINT && received != SIGTERM && received != SIGHUP) continue;  // timeout or EINTR
    Take(received);
  }
}

void InterruptAtBoundary::Take(int received) {
  if (Requested()) {
    std::fputs("\ninterrupted again: stopping now\n", stderr);
    std::_Exit(InterruptExitCode(received));
  }
  signal_ = received;
  std::fprintf(stderr, "\n%s\n", message_.c_str());
}

}  // namespace ipmc
