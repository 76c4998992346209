#pragma once
// What a periodic loop runs (src/core/rt/periodic_loop.h runs it on a thread or in simulated time).

#include <cstdint>

namespace robossis::rt {

// Tick() is real-time code: noexcept, allocation-free, lock-free, prints nothing.
class PeriodicTask {
 public:
  virtual ~PeriodicTask() = default;
  // now_ns: the runtime clock at the tick's start (MonotonicClock or SimulatedClock time, ns since its epoch).
  virtual void Tick(std::int64_t now_ns) noexcept = 0;
};

}  // namespace robossis::rt
