// A long simulation as the command line shows it: its simulated time as a
// progress bar on stderr (sim/io/progress_bar.h), and SIGINT or SIGTERM
// stopping it at the next safe point (sim/cli/interrupt.h). The run calls
// At() at its safe points (every recorded sample); after a stop request,
// At() throws Interrupted, whose unwinding removes what was not finished.
#pragma once

#include <string>

#include "sim/cli/interrupt.h"
#include "sim/io/progress_bar.h"

namespace ipmc {

class RunWatch {
 public:
  // `what` names the job in plain lines ("running"); total_s is the
  // simulated time it will reach [s].
  RunWatch(const std::string& what, double total_s);

  // At simulated time t_s: redraws the bar; throws Interrupted "stopped at
  // t = T s of TOTAL s; NOT_WRITTEN" if a stop was requested.
  void At(double t_s);
  // Ends the bar's line.
  void Finish();

  // What a stop leaves unwritten, for its message ("nothing written").
  void SetNotWritten(std::string text) { not_written_ = std::move(text); }
  const InterruptAtBoundary& interrupt() const { return interrupt_; }

 private:
  InterruptAtBoundary interrupt_;
  ProgressBar bar_;
  double total_s_;
  int shown_s_ = -1;
  std::string not_written_ = "nothing written";
};

}  // namespace ipmc
