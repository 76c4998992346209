#pragma once
// The E-stop as a latched level that no queue can push out: a count of E-stops engaged, only ever increased. Any
// number of producers engage it (an atomic add: lock-free, allocation-free, never refused); the follower unit reads
// it first thing every tick and E-stops when it has grown. A count rather than a flag, so that two E-stops engaged
// between two reads are never merged into none (a flag set, cleared by one reader and set again would be).

#include <atomic>
#include <cstdint>

namespace robossis::teleop {

class EStopLatch {
 public:
  void Engage() noexcept { engaged_.fetch_add(1, std::memory_order_release); }
  std::uint64_t engaged() const noexcept { return engaged_.load(std::memory_order_acquire); }

 private:
  std::atomic<std::uint64_t> engaged_{0};
};

}  // namespace robossis::teleop
