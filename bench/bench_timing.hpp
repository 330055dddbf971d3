// Timing for the benchmarks: CPU clocks (less disturbed than wall time when other jobs share the
// cores) and the best-of-repeats measurements every benchmark prints its ratios from.
#pragma once

#include <time.h>

#include <algorithm>
#include <ctime>
#include <functional>

namespace pcsim_bench {

/// CPU time of the whole process (all threads), seconds.
inline double process_cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

/// CPU time of the calling thread, seconds (excludes helper threads such as an output writer).
inline double thread_cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// Seconds of process CPU per call of f: calls in batches of `batch` until `min_seconds` have
/// passed, the best of `repeats` such measurements.
inline double seconds_per_call(const std::function<void()>& f, int repeats, int batch = 100,
                               double min_seconds = 0.1) {
  double best = 1e300;
  for (int rep = 0; rep < repeats; ++rep) {
    long calls = 0;
    const double start = process_cpu_seconds();
    double elapsed = 0.0;
    do {
      for (int k = 0; k < batch; ++k) f();
      calls += batch;
      elapsed = process_cpu_seconds() - start;
    } while (elapsed < min_seconds);
    best = std::min(best, elapsed / static_cast<double>(calls));
  }
  return best;
}

/// The least thread CPU time of `repeats` calls of f, seconds.
template <class F> double min_thread_time(int repeats, F&& f) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const double t0 = thread_cpu_seconds();
    f();
    best = std::min(best, thread_cpu_seconds() - t0);
  }
  return best;
}

}  // namespace pcsim_bench
