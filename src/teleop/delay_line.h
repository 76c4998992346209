#pragma once
// A fixed transport delay between two threads: what one side sends at t arrives at the other at t + delay, newest
// first ("latest" semantics, as the link's snapshots), older ones behind it dropped as a newer one arrives. Models
// the one-way delay of a network link in one process (`robossis teleop --link-delay-ms`).
//
// One producer thread (Send), one consumer thread (Take). Lock-free and allocation-free after construction (an
// SpscQueue sized for the delay at the sender's rate; a full queue drops the message and counts it, as a congested
// link would).

#include <atomic>
#include <cstdint>

#include "src/core/rt/spsc_queue.h"

namespace robossis::teleop {

template <typename T>
class DelayLine {
 public:
  DelayLine(std::int64_t delay_ns, std::size_t capacity) : delay_ns_(delay_ns), queue_(capacity) {}

  void Send(const T& value, std::int64_t now_ns) noexcept {
    if (!queue_.TryPush(Entry{value, now_ns + delay_ns_})) dropped_.fetch_add(1, std::memory_order_relaxed);
  }
  // The newest message due by now_ns; false if none became due since the last call. `due_ns`: when it arrived.
  bool Take(std::int64_t now_ns, T& value, std::int64_t& due_ns) noexcept {
    bool got = false;
    while (has_pending_ || queue_.TryPop(pending_)) {
      has_pending_ = true;
      if (pending_.due_ns > now_ns) break;
      value = pending_.value;
      due_ns = pending_.due_ns;
      has_pending_ = false;
      got = true;
    }
    return got;
  }
  std::int64_t delay_ns() const noexcept { return delay_ns_; }
  std::uint64_t dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }

 private:
  struct Entry {
    T value;
    std::int64_t due_ns = 0;
  };
  std::int64_t delay_ns_;
  rt::SpscQueue<Entry> queue_;
  Entry pending_{};  // consumer side: the oldest message not yet due
  bool has_pending_ = false;
  std::atomic<std::uint64_t> dropped_{0};
};

}  // namespace robossis::teleop
