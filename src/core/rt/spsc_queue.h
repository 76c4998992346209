#pragma once
// A bounded lock-free single-producer single-consumer ring: how a real-time loop hands records to the non-real-time
// side (logging, the panel) and receives commands from it. Push and Pop never allocate, lock or throw; the storage
// is allocated once, at construction. A full queue refuses the push (the producer counts the drop): a real-time
// producer never waits for its consumer.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>

namespace robossis::rt {

template <typename T>
class SpscQueue {
  static_assert(std::is_nothrow_copy_assignable_v<T> && std::is_trivially_destructible_v<T>,
                "SpscQueue holds plain records (fixed-size Eigen members are fine), copied by value");

 public:
  // Capacity is rounded up to a power of two.
  explicit SpscQueue(std::size_t min_capacity) : capacity_(RoundUp(min_capacity)), mask_(capacity_ - 1),
                                                 slots_(std::make_unique<T[]>(capacity_)) {}

  // Producer only. False (and nothing written) when full.
  bool TryPush(const T& value) noexcept {
    const std::uint64_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_cache_ >= capacity_) {
      tail_cache_ = tail_.load(std::memory_order_acquire);
      if (head - tail_cache_ >= capacity_) return false;
    }
    slots_[head & mask_] = value;
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  // Consumer only. False when empty.
  bool TryPop(T& value) noexcept {
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_cache_) {
      head_cache_ = head_.load(std::memory_order_acquire);
      if (tail == head_cache_) return false;
    }
    value = slots_[tail & mask_];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  // Approximate (exact when called by either end while the other is idle).
  std::size_t size() const noexcept {
    return static_cast<std::size_t>(head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire));
  }
  std::size_t capacity() const noexcept { return capacity_; }

 private:
  static std::size_t RoundUp(std::size_t n) {
    std::size_t c = 1;
    while (c < n) c <<= 1;
    return c;
  }
  const std::size_t capacity_;
  const std::size_t mask_;
  std::unique_ptr<T[]> slots_;
  alignas(64) std::atomic<std::uint64_t> head_{0};  // written by the producer
  std::uint64_t tail_cache_ = 0;                    // producer's copy of tail_
  alignas(64) std::atomic<std::uint64_t> tail_{0};  // written by the consumer
  std::uint64_t head_cache_ = 0;                    // consumer's copy of head_
};

}  // namespace robossis::rt
