// Ctrl-C at a point boundary. While an InterruptAtBoundary lives, SIGINT
// does not kill the process: the first one makes Requested() true (the
// work stops starting new pieces and finishes those running) and prints
// `message` on stderr; a second one ends the process at once with exit
// code 130, as the default action would.
//
// SIGINT is blocked in the constructing thread, and so in every thread it
// starts afterwards (they inherit the mask); a watcher thread takes the
// signal with sigtimedwait, so there is no signal handler and no global
// state. Construct it before starting any worker thread.
#pragma once

#include <signal.h>

#include <atomic>
#include <string>
#include <thread>

namespace ipmc {

class InterruptAtBoundary {
 public:
  explicit InterruptAtBoundary(std::string message);
  ~InterruptAtBoundary();
  InterruptAtBoundary(const InterruptAtBoundary&) = delete;
  InterruptAtBoundary& operator=(const InterruptAtBoundary&) = delete;

  bool Requested() const { return requested_; }

 private:
  void Watch();

  std::string message_;
  sigset_t previous_mask_;
  std::atomic<bool> requested_{false};
  std::atomic<bool> finished_{false};
  std::thread watcher_;
};

}  // namespace ipmc
