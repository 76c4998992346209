#pragma once
// The one clock of the runtime. Loops, devices and the follower read time only through a Clock, so the same units
// run on wall-clock deadlines (MonotonicClock, CLOCK_MONOTONIC) or deterministically in simulated time
// (SimulatedClock, advanced by whoever drives the simulation), as `robossis teleop --clock real|simulated` selects.

#include <atomic>
#include <cstdint>

namespace robossis::rt {

class Clock {
 public:
  virtual ~Clock() = default;
  // Seconds since an arbitrary epoch fixed for the clock's lifetime. Lock-free, allocation-free.
  virtual double NowS() const noexcept = 0;
};

// CLOCK_MONOTONIC, in seconds since the clock was made.
class MonotonicClock final : public Clock {
 public:
  MonotonicClock() noexcept;
  double NowS() const noexcept override;
  // The raw CLOCK_MONOTONIC reading (ns) at this clock's zero: absolute deadlines for clock_nanosleep.
  std::int64_t epoch_ns() const noexcept { return epoch_ns_; }

 private:
  std::int64_t epoch_ns_;
};

// Simulated time in integer nanoseconds (no drift from summing doubles). One thread advances it; any thread reads.
class SimulatedClock final : public Clock {
 public:
  double NowS() const noexcept override { return 1e-9 * static_cast<double>(now_ns_.load(std::memory_order_acquire)); }
  std::int64_t now_ns() const noexcept { return now_ns_.load(std::memory_order_acquire); }
  void AdvanceNs(std::int64_t dt_ns) noexcept { now_ns_.fetch_add(dt_ns, std::memory_order_acq_rel); }
  void SetNs(std::int64_t t_ns) noexcept { now_ns_.store(t_ns, std::memory_order_release); }

 private:
  std::atomic<std::int64_t> now_ns_{0};
};

// CLOCK_MONOTONIC now, in ns.
std::int64_t MonotonicNowNs() noexcept;

}  // namespace robossis::rt
