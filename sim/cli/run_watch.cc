#include "sim/cli/run_watch.h"

#include <algorithm>
#include <cmath>

#include "sim/io/numbers.h"

namespace ipmc {
namespace {

// Off a terminal, runs shorter than this print no progress lines.
constexpr double kQuiet_s = 5.0;

}  // namespace

RunWatch::RunWatch(const std::string& what, double total_s)
    : interrupt_("interrupted: stopping at the next recorded sample (again: at once)"),
      bar_(what, "s simulated", StderrIsTerminal(), /*quarter_lines=*/true, kQuiet_s),
      total_s_(total_s) {
  bar_.Start(std::max(1, static_cast<int>(std::ceil(total_s_))));
}

void RunWatch::At(double t_s) {
  const int whole_s = static_cast<int>(std::floor(std::min(t_s, total_s_)));
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
