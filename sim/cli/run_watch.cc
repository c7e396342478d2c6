#include "sim/cli/run_watch.h"

#include <algorithm>
#include <cmath>

#include "sim/base/numbers.h"

namespace ipmc {
namespace {

// Off a terminal, runs shorter than this print no progress lines.
constexpr double kQuiet_s = 5.0;

// Whole simulated seconds for the bar, at least 1. The watch starts before
// the run checks its length, so an absurd or non-finite total (which the
// run then refuses) must still convert to int without overflow.
int ProgressUnits(double total_s) {
  constexpr double kMaxUnits = 1e9;
  if (!std::isfinite(total_s)) return 1;
  return static_cast<int>(std::clamp(std::ceil(total_s), 1.0, kMaxUnits));
}

}  // namespace

RunWatch::RunWatch(const std::string& what, double total_s)
    : interrupt_("interrupted: stopping at the next recorded sample (again: at once)"),
      bar_(what, "s simulated", StderrIsTerminal(), /*quarter_lines=*/true, kQuiet_s),
      total_s_(total_s) {
  bar_.Start(ProgressUnits(total_s));
}

void RunWatch::At(double t_s) {
  const int whole_s = std::min(static_cast<int>(std::floor(std::max(t_s, 0.0))),
                               ProgressUnits(total_s_));
  if (whole_s != shown_s_) {
    bar_.Update(whole_s);
    shown_s_ = whole_s;
  }
  if (!interrupt_.Requested()) return;
  interrupt_.ThrowIfRequested(FormatText("stopped at t = %.4g s of %.4g s; %s", t_s, total_s_,
                                         not_written_.c_str()));
}

void RunWatch::Finish() { bar_.Finish(); }

}  // namespace ipmc
