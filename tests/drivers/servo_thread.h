#pragma once
// The follower unit's servo loop for the HAL tests and benchmarks: a thread that calls body(follower, now_s) and
// then Service(now_s) on absolute deadlines of the HAL servo period.

#include <pthread.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <limits>
#include <mutex>  // std::lock_guard
#include <optional>
#include <thread>

#include "robot/drivers/hal_follower.h"
#include "src/core/rt/clock.h"

namespace robossis::testing {

using drivers::HalFollower;

// A mutex with priority inheritance: a test thread (normal priority) preempted on a loaded machine while it holds
// the loop's lock runs at the loop's priority until it lets go. With a plain mutex that priority inversion stalled
// the loop past half the follower timeout, and the follower rightly latched a drive fault.
class PriorityInheritanceMutex {
 public:
  PriorityInheritanceMutex() {
    pthread_mutexattr_t attributes;
    pthread_mutexattr_init(&attributes);
    pthread_mutexattr_setprotocol(&attributes, PTHREAD_PRIO_INHERIT);
    pthread_mutex_init(&mutex_, &attributes);
    pthread_mutexattr_destroy(&attributes);
  }
  ~PriorityInheritanceMutex() { pthread_mutex_destroy(&mutex_); }
  PriorityInheritanceMutex(const PriorityInheritanceMutex&) = delete;
  PriorityInheritanceMutex& operator=(const PriorityInheritanceMutex&) = delete;
  void lock() { pthread_mutex_lock(&mutex_); }
  void unlock() { pthread_mutex_unlock(&mutex_); }

 private:
  pthread_mutex_t mutex_;
};

// The follower unit's servo thread: on absolute deadlines of the HAL servo period, body(now_s) then Service(now_s).
// The test thread reaches the follower only through With(), which holds the loop's lock (holding it stalls the loop).
class ServoThread {
 public:
  using Body = std::function<void(HalFollower&, double)>;
  // period_ns 0: the HAL servo period.
  ServoThread(HalFollower& follower, const rt::MonotonicClock& clock, Body body = {}, std::int64_t period_ns = 0)
      : follower_(follower),
        clock_(clock),
        body_(std::move(body)),
        period_(period_ns > 0 ? period_ns : follower.config().servo_period_ns),
        thread_([this] { Loop(); }) {}
  ~ServoThread() {
    stop_ = true;
    thread_.join();
  }
  template <class F>
  auto With(F&& f) {
    std::lock_guard<PriorityInheritanceMutex> lock(mutex_);
    return f(follower_);
  }
  // From now on, remember the state after the first Service() that starts later than this call.
  void Mark() {
    std::lock_guard<PriorityInheritanceMutex> lock(mutex_);
    mark_s_ = clock_.NowS();
    after_mark_.reset();
  }
  std::optional<robot::RsrFollowerState> StateAfterMark() {
    std::lock_guard<PriorityInheritanceMutex> lock(mutex_);
    return after_mark_;
  }
  static void Sleep(double s) { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }
  // Polls `done` every millisecond until it holds or `timeout_s` of wall-clock time passed; returns its last value.
  // For what takes HAL's or this loop's periods to come true: waited for rather than slept for, so that a loaded
  // machine only makes it later (the timeout is generous, a bound on a hang, not a timing check).
  template <class F>
  static bool Eventually(F&& done, double timeout_s = 30) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    for (;;) {
      if (done()) return true;
      if (std::chrono::steady_clock::now() > until) return done();
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }

 private:
  void Loop() {
    // A follower unit runs its servo loop at a real-time priority; where allowed (root), so does this one, so that
    // a loaded machine does not stall it past the watchdogs. Without the privilege it runs at normal priority.
    const sched_param param{.sched_priority = 50};
    pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
    const auto period = std::chrono::nanoseconds(period_);
    auto deadline = std::chrono::steady_clock::now();
    while (!stop_) {
      deadline += period;
      std::this_thread::sleep_until(deadline);
      std::lock_guard<PriorityInheritanceMutex> lock(mutex_);
      const double now = clock_.NowS();
      if (body_) body_(follower_, now);
      follower_.Service(now);
      if (now > mark_s_ && !after_mark_) after_mark_ = follower_.State();
      // After a stall, carry on from now rather than catching up on the missed periods.
      if (std::chrono::steady_clock::now() > deadline + 10 * period) deadline = std::chrono::steady_clock::now();
    }
  }

  HalFollower& follower_;
  const rt::MonotonicClock& clock_;
  Body body_;
  std::int64_t period_;
  PriorityInheritanceMutex mutex_;
  double mark_s_ = std::numeric_limits<double>::infinity();
  std::optional<robot::RsrFollowerState> after_mark_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace robossis::testing
