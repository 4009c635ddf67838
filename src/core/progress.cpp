#include "bridgefit/core/progress.hpp"

#include <cstdio>
#include <unistd.h>

namespace bridgefit {

Progress::Progress(std::string label, std::size_t total, bool enabled, double delay_s)
    : label_(std::move(label)),
      total_(total),
      enabled_(enabled),
      delay_s_(delay_s),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

Progress::~Progress() { Finish(); }

double Progress::ElapsedSeconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::Update(std::size_t done) {
  if (!enabled_ || finished_) return;
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (elapsed < delay_s_) return;
  if (shown_ && std::chrono::duration<double>(now - last_draw_).count() < 0.2) return;
  last_draw_ = now;
  shown_ = true;
  // A carriage return redraws in place on a terminal; plain lines otherwise.
  const bool tty = isatty(fileno(stderr)) != 0;
  if (total_ > 0) {
    const double fraction = static_cast<double>(done) / static_cast<double>(total_);
    const double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    std::fprintf(stderr, "%s%s: %zu/%zu (%.0f%%), %.1f s elapsed, ~%.1f s left%s",
                 tty ? "\r" : "", label_.c_str(), done, total_, 100.0 * fraction, elapsed,
                 eta, tty ? "   " : "\n");
  } else {
    std::fprintf(stderr, "%s%s: %zu done, %.1f s elapsed%s", tty ? "\r" : "", label_.c_str(),
                 done, elapsed, tty ? "   " : "\n");
  }
  std::fflush(stderr);
}

void Progress::Finish() {
  if (finished_) return;
  finished_ = true;
  if (enabled_ && shown_) {
    const bool tty = isatty(fileno(stderr)) != 0;
    std::fprintf(stderr, "%s%s: done in %.1f s\n", tty ? "\r" : "", label_.c_str(),
                 ElapsedSeconds());
  }
}

}  // namespace bridgefit
