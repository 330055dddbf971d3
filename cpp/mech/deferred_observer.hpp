// Issue 23: an observer that only reads (the time-series rows, the window extremes) runs on a
// thread of its own, behind the integration, instead of on the integrating thread: simulate()'s
// observer calls push(view), which records the step (the state at its end and the dense output's
// polynomial, a few hundred bytes) and returns; the thread replays the steps in order
// (StepReplayer), with a workspace of its own, so the observer sees the same samples bit for bit
// as it would have in place. On the paper's case the rows' samples were 17 % of the integrating
// thread.
//
//   DeferredObserver deferred([&](const StepView& v) { return monitor.observe(v); });
//   simulate(model, q0, qd0, options, [&](const StepView& v) { return deferred.push(v); });
//   deferred.finish();  // every step observed; the observer's failure, if any, in error()
//
// The observer runs on one thread at a time and sees the steps in order; it must not stop the
// run (returning false or throwing stops observing: push() then answers false and the run
// stops, error() says why). A view that cannot be recorded (the switching driver's) is observed
// in place once the steps before it are. Without a second hardware thread, or with threaded =
// false, every step is observed in place.
#pragma once

#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "mech/simulation.hpp"

namespace pcsim::mech {

class DeferredObserver {
 public:
  explicit DeferredObserver(StepObserver observer, bool threaded = true);
  /// finish(): the thread is joined before the observer's captures go.
  ~DeferredObserver();
  DeferredObserver(const DeferredObserver&) = delete;
  DeferredObserver& operator=(const DeferredObserver&) = delete;

  /// Hands one step over (in place where it cannot be recorded). false: observing has failed
  /// (error() says why); stop the run.
  bool push(const StepView& v);
  /// Waits until every step pushed has been observed. Idempotent.
  void finish();
  /// Why observing stopped ("" while it has not): the observer returned false or threw.
  std::string error() const;
  /// Whether the steps go to a thread of their own.
  bool threaded() const { return threaded_; }

  /// Steps in flight at most (beyond, the integrating thread waits until half of them are
  /// observed), and the batch after which a waiting observer thread is woken (one wake-up per
  /// step would cost a system call each).
  static constexpr std::size_t kCapacity = 256, kBatch = 16;

 private:
  void work();
  bool observe_here(const StepView& v);
  void drain(std::unique_lock<std::mutex>& lock);

  StepObserver observer_;
  bool threaded_;
  StepReplayer replayer_;
  std::vector<StepRecord> ring_;
  std::size_t head_ = 0, count_ = 0;
  mutable std::mutex mutex_;
  std::condition_variable work_cv_, space_cv_;
  bool done_ = false, worker_waiting_ = false, pusher_waiting_ = false, failed_ = false;
  std::string error_;
  std::thread thread_;
};

}  // namespace pcsim::mech
