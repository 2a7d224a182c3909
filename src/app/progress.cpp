#include "app/progress.h"

#include <unistd.h>
#include <cstdio>

namespace bounce::app {

ProgressBar::ProgressBar(std::string label, std::uint64_t total)
    : label_(std::move(label)),
      total_(total),
      enabled_(isatty(STDERR_FILENO) && total > 1),
      start_(std::chrono::steady_clock::now()),
      lastDraw_(start_) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(std::uint64_t done) {
  if (!enabled_ || finished_) return;
  auto now = std::chrono::steady_clock::now();
  // Redraw at most 10 times a second: drawing is not free on a fast loop.
  if (done < total_ && now - lastDraw_ < std::chrono::milliseconds(100)) return;
  lastDraw_ = now;
  constexpr int kWidth = 30;
  const double fraction = total_ ? double(done) / double(total_) : 1.0;
  const int filled = int(fraction * kWidth);
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double remaining = done ? elapsed * double(total_ - done) / double(done) : 0.0;
  std::fprintf(stderr, "\r%s [%.*s%*s] %llu/%llu  %.1fs left ", label_.c_str(), filled,
               "==============================", kWidth - filled, "", static_cast<unsigned long long>(done),
               static_cast<unsigned long long>(total_), remaining);
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (!enabled_ || finished_) return;
  update(total_);
  finished_ = true;
  std::fprintf(stderr, "\n");
}

}  // namespace bounce::app
