#include "sim/io/progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace ipmc {
namespace {

constexpr int kBarWidth = 30;

}  // namespace

std::string Clock(double seconds) {
  const long total = std::max(0L, static_cast<long>(seconds + 0.5));
  char buffer[32];
  if (total >= 3600) {
    std::snprintf(buffer, sizeof(buffer), "%ld:%02ld:%02ld", total / 3600, total / 60 % 60,
                  total % 60);
  } else {
    std::snprintf(buffer, sizeof(buffer), "%ld:%02ld", total / 60, total % 60);
  }
  return buffer;
}

bool StderrIsTerminal() { return isatty(STDERR_FILENO) == 1; }

ProgressBar::ProgressBar(std::string what, std::string unit, bool terminal, bool quarter_lines)
    : what_(std::move(what)), unit_(std::move(unit)), terminal_(terminal),
      quarter_lines_(quarter_lines) {}

double ProgressBar::elapsed_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressBar::Start(int total) {
  total_ = total;
  quarters_shown_ = 0;
  start_ = std::chrono::steady_clock::now();
  if (terminal_ && total > 0) {
    Draw("[" + std::string(kBarWidth, '-') + "] 0/" + std::to_string(total) + " " + unit_);
  }
}

void ProgressBar::Update(int done, const std::string& note) {
  const double elapsed = elapsed_s();
  if (!terminal_) {
    if (!quarter_lines_ || total_ <= 0) return;
    const int quarters = 4 * done / total_;
    if (quarters > quarters_shown_) {
      quarters_shown_ = quarters;
      std::fprintf(stderr, "%s: %d/%d %s (%d %%), %s elapsed\n", what_.c_str(), done, total_,
                   unit_.c_str(), 100 * done / total_, Clock(elapsed).c_str());
    }
    return;
  }
  const int filled = total_ > 0 ? kBarWidth * std::min(done, total_) / total_ : kBarWidth;
  const double remaining_s = done > 0 ? elapsed / done * (total_ - done) : 0.0;
  std::string line = "[" + std::string(filled, '#') + std::string(kBarWidth - filled, '-') + "] " +
                     std::to_string(done) + "/" + std::to_string(total_) + " " + unit_ + ", " +
                     Clock(elapsed) + " elapsed, ETA " + Clock(remaining_s);
  if (!note.empty()) line += ", " + note;
  Draw(line);
}

void ProgressBar::Draw(const std::string& text) {
  std::string line = "\r" + text;
  const size_t width = text.size();
  if (width < last_width_) line += std::string(last_width_ - width, ' ');
  last_width_ = width;
  std::fputs(line.c_str(), stderr);
  std::fflush(stderr);
}

void ProgressBar::Finish() {
  if (terminal_ && last_width_ > 0) std::fputc('\n', stderr);
  last_width_ = 0;
}

}  // namespace ipmc
