// Progress bar with rate and ETA on stderr.
#include "study/progress.hpp"

#include <cstdio>
#include <string>

#include <unistd.h>

namespace pcsim::study {

bool stderr_is_terminal() { return isatty(STDERR_FILENO) == 1; }

Progress::Progress(std::size_t total, std::size_t done, bool enabled)
    : total_(total), done_(done), start_done_(done), enabled_(enabled),
      start_(std::chrono::steady_clock::now()), last_draw_(start_) {
  if (enabled_) draw();
}

void Progress::tick() {
  ++done_;
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (done_ == total_ || now - last_draw_ > std::chrono::milliseconds(200)) draw();
}

void Progress::finish() {
  if (!enabled_) return;
  draw();
  std::fputc('\n', stderr);
  std::fflush(stderr);
  enabled_ = false;
}

void Progress::draw() {
  last_draw_ = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(last_draw_ - start_).count();
  const std::size_t ran = done_ - start_done_;
  const double rate = elapsed > 0 && ran > 0 ? static_cast<double>(ran) / elapsed : 0.0;
  constexpr int kWidth = 30;
  const int filled = total_ ? static_cast<int>(kWidth * done_ / total_) : kWidth;
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(kWidth, '.');
  char eta[32] = "--:--";
  if (rate > 0) {
    const long s = static_cast<long>(static_cast<double>(total_ - done_) / rate + 0.5);
    std::snprintf(eta, sizeof eta, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  }
  std::fprintf(stderr, "\r[%s] %zu/%zu %5.1f%%  %.2f pts/s  ETA %s ", bar.c_str(), done_, total_,
               total_ ? 100.0 * static_cast<double>(done_) / static_cast<double>(total_) : 100.0,
               rate, eta);
  std::fflush(stderr);
}

}  // namespace pcsim::study
