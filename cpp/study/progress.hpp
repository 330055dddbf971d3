// A progress bar with rate and ETA on stderr, for a terminal only (the caller decides).
#pragma once

#include <chrono>
#include <cstddef>

namespace pcsim::study {

class Progress {
 public:
  /// `total` points, `done` of them finished before this run (not counted in the rate).
  Progress(std::size_t total, std::size_t done, bool enabled);
  /// One more point finished; redraws at most every 0.2 s (and at the last point).
  void tick();
  /// Ends the bar's line.
  void finish();

 private:
  void draw();
  std::size_t total_, done_, start_done_;
  bool enabled_;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

/// True when stderr is a terminal.
bool stderr_is_terminal();

}  // namespace pcsim::study
