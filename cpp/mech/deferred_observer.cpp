#include "mech/deferred_observer.hpp"

#include <exception>
#include <system_error>
#include <utility>

#include "common/format.hpp"

namespace pcsim::mech {

DeferredObserver::DeferredObserver(StepObserver observer, bool threaded)
    : observer_(std::move(observer)), threaded_(threaded && std::thread::hardware_concurrency() > 1) {
  if (!threaded_) return;
  ring_.resize(kCapacity);
  try {
    thread_ = std::thread(&DeferredObserver::work, this);
  } catch (const std::system_error&) {
    threaded_ = false;  // no thread to be had: every step is observed in place
  }
}

DeferredObserver::~DeferredObserver() { finish(); }

namespace {

// Why an observer stopped, as simulate() words it for an observer in place.
std::string stop_message(double t) {
  return "the step observer stopped observing at t = " + format_significant(t, 9);
}

std::string thrown_message() {
  try {
    throw;
  } catch (const std::exception& ex) {
    return std::string("the step observer threw: ") + ex.what();
  } catch (...) {
    return "the step observer threw an unknown exception";
  }
}

}  // namespace

bool DeferredObserver::observe_here(const StepView& v) {
  std::string why;
  try {
    if (observer_(v)) return true;
    why = stop_message(v.t);
  } catch (...) {
    why = thrown_message();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  failed_ = true;
  error_ = std::move(why);
  return false;
}

bool DeferredObserver::push(const StepView& v) {
  if (!threaded_) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (failed_) return false;
    }
    return observe_here(v);
  }
  std::unique_lock<std::mutex> lock(mutex_);
  if (failed_ || done_) return false;
  if (count_ == kCapacity) {
    // Full: wait until the observer has caught up by half the ring, not for one slot (one
    // wake-up per step, each a system call, would set the pace of both threads).
    if (worker_waiting_) work_cv_.notify_one();
    while (count_ > kCapacity / 2) {
      pusher_waiting_ = true;
      space_cv_.wait(lock);
      pusher_waiting_ = false;
    }
  }
  // The slot past the last one in flight: the observer's thread does not touch it until count_
  // says so.
  StepRecord& slot = ring_[(head_ + count_) % kCapacity];
  lock.unlock();
  const bool recorded = v.record(slot);
  lock.lock();
  if (!recorded) {
    drain(lock);
    if (failed_) return false;
    lock.unlock();
    return observe_here(v);
  }
  ++count_;
  if (worker_waiting_ && count_ >= kBatch) work_cv_.notify_one();
  return !failed_;
}

// Waits until every step in flight has been observed.
void DeferredObserver::drain(std::unique_lock<std::mutex>& lock) {
  if (count_ > 0) work_cv_.notify_one();
  while (count_ > 0) {
    pusher_waiting_ = true;
    space_cv_.wait(lock);
    pusher_waiting_ = false;
  }
}

void DeferredObserver::finish() {
  if (!threaded_) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    done_ = true;
  }
  work_cv_.notify_one();
  if (thread_.joinable()) thread_.join();
}

std::string DeferredObserver::error() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return error_;
}

void DeferredObserver::work() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    while (count_ == 0 && !done_) {
      worker_waiting_ = true;
      work_cv_.wait(lock);
      worker_waiting_ = false;
    }
    if (count_ == 0) return;  // done_, and every step observed
    const StepRecord& record = ring_[head_];
    const bool skip = failed_;  // after a failure the steps are only taken off the ring
    lock.unlock();
    std::string why;
    if (!skip) {
      try {
        if (!replayer_.replay(record, observer_)) why = stop_message(record.t);
      } catch (...) {
        why = thrown_message();
      }
    }
    lock.lock();
    if (!why.empty()) {
      failed_ = true;
      error_ = std::move(why);
    }
    head_ = (head_ + 1) % kCapacity;
    --count_;
    if (pusher_waiting_ && count_ <= kCapacity / 2) space_cv_.notify_one();
  }
}

}  // namespace pcsim::mech
