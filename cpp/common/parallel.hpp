// pcsim's one thread pool: independent work items, numbered 0..count-1, taken in turn by a set
// of threads (the sweep's points, the response's orbits). Each item's result goes to its own
// index, so the outcome does not depend on which thread ran what.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <functional>
#include <thread>
#include <vector>

namespace pcsim {

/// Threads that run f(i) for every i < count, each item once; started by the constructor and
/// joined by join() (or the destructor). f must not throw (catch per item).
class Workers {
 public:
  /// `jobs` threads (0: one per hardware thread), never more than `count`.
  Workers(std::size_t count, unsigned jobs, std::function<void(std::size_t)> f)
      : count_(count), f_(std::move(f)) {
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    const std::size_t n = std::min<std::size_t>(jobs ? jobs : hw, count);
    for (std::size_t t = 0; t < n; ++t)
      threads_.emplace_back([this] {
        for (std::size_t i = next_++; i < count_; i = next_++) f_(i);
      });
  }
  Workers(const Workers&) = delete;
  Workers& operator=(const Workers&) = delete;
  ~Workers() { join(); }

  void join() {
    for (auto& t : threads_)
      if (t.joinable()) t.join();
  }

 private:
  std::size_t count_;
  std::function<void(std::size_t)> f_;
  std::atomic<std::size_t> next_{0};
  std::vector<std::thread> threads_;
};

/// Runs f(i) for every i < count on `jobs` threads (0: one per hardware thread) and returns
/// when all are done.
inline void parallel_for(std::size_t count, unsigned jobs, std::function<void(std::size_t)> f) {
  Workers(count, jobs, std::move(f)).join();
}

}  // namespace pcsim
