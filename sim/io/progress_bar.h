// Progress of a long job on stderr. On a terminal, a bar redrawn in place:
//   [##########--------------------] 10/30 runs, 0:05 elapsed, ETA 0:10
// Elsewhere (logs, pipes) the bar is not drawn; with `quarter_lines` it
// prints one plain line as each quarter of the job is done instead
// ("rendering: 150/300 frames (50 %)"), otherwise nothing, and the caller
// may print its own lines.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace ipmc {

// "m:ss", or "h:mm:ss" from an hour on.
std::string Clock(double seconds);

// Whether stderr is a terminal.
bool StderrIsTerminal();

class ProgressBar {
 public:
  // `what` names the job in plain lines ("rendering"), `unit` the steps
  // ("frames").
  ProgressBar(std::string what, std::string unit, bool terminal, bool quarter_lines = false);

  // Draws the empty bar (so that a long first step does not look like a
  // hang) and starts the clock.
  void Start(int total);
  // `done` of the total steps are finished; `note` is appended to the bar.
  void Update(int done, const std::string& note = "");
  // Ends the bar's line.
  void Finish();

  bool terminal() const { return terminal_; }
  double elapsed_s() const;

 private:
  void Draw(const std::string& line);

  std::string what_, unit_;
  bool terminal_, quarter_lines_;
  int total_ = 0;
  int quarters_shown_ = 0;
  size_t last_width_ = 0;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace ipmc
