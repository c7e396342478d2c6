// Stopping at a safe point on SIGINT (Ctrl-C), SIGTERM (kill, a cluster's
// time limit) or SIGHUP (the terminal closed, treated as SIGTERM: the same
// stop and the same exit code, 143; messages name the signal received).
// While an InterruptAtBoundary lives, none of them kills the
// process: the first one makes Requested() true and prints `message` on
// stderr; the work checks Requested() at its safe points (a sweep between
// points, a run at each recorded sample, a film at each frame, a merge
// before it writes), stops there, and its unwinding removes the
// temporaries of unfinished outputs. A second signal ends the process at
// once with the same exit code.
//
// Both signals are blocked in the constructing thread, and so in every
// thread it starts afterwards (they inherit the mask); a watcher thread
// takes them with sigtimedwait, so there is no signal handler and no
// global state. A signal already pending when it is constructed (sent
// while the process blocked it) counts as received then. Construct it
// before starting any worker thread.
#pragma once

#include <signal.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <thread>

namespace ipmc {

// What a command throws at the safe point where it stops; main prints
// "ipmc-swim: interrupted by SIG...: WHAT" and exits with ExitCode().
class Interrupted : public std::runtime_error {
 public:
  Interrupted(int signal, const std::string& what) : std::runtime_error(what), signal_(signal) {}
  int signal() const { return signal_; }
  // The exit code: the shell's for a process the signal stopped, 128 +
  // signal (130 for SIGINT, 143 for SIGTERM), SIGTERM's for SIGHUP.
  int ExitCode() const;
  // "SIGINT", "SIGTERM" or "SIGHUP".
  std::string SignalName() const;

 private:
  int signal_;
};

// 128 + signal, SIGTERM's for SIGHUP.
int InterruptExitCode(int signal);

class InterruptAtBoundary {
 public:
  explicit InterruptAtBoundary(std::string message);
  ~InterruptAtBoundary();
  InterruptAtBoundary(const InterruptAtBoundary&) = delete;
  InterruptAtBoundary& operator=(const InterruptAtBoundary&) = delete;

  bool Requested() const { return signal_ != 0; }
  // The signal that requested the stop (SIGINT, SIGTERM or SIGHUP), 0 if none.
  int signal() const { return signal_; }
  // Throws Interrupted(signal(), what) if a stop was requested.
  void ThrowIfRequested(const std::string& what) const;

 private:
  void Watch();
  // Requests the stop for `received`; a second signal ends the process.
  void Take(int received);

  std::string message_;
  sigset_t previous_mask_;
  std::atomic<int> signal_{0};
  std::atomic<bool> finished_{false};
  std::thread watcher_;
};

}  // namespace ipmc
