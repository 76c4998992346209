#pragma once
// The latest value of a record, published by one writer and read by any number of readers without locks
// (a sequence lock). The writer never waits; a reader retries while a write is in progress and gets a consistent
// copy. How the panel, the logger and the other unit read a loop's state.

#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace robossis::rt {

template <typename T>
class Snapshot {
  // Plain records: trivially destructible and copyable as bytes (fixed-size Eigen members are fine, though Eigen
  // does not declare them trivially copyable).
  static_assert(std::is_trivially_destructible_v<T> && std::is_default_constructible_v<T>,
                "Snapshot holds plain records, copied by value");

 public:
  // Writer only. Wait-free, allocation-free.
  void Publish(const T& value) noexcept {
    const std::uint64_t s = seq_.load(std::memory_order_relaxed);
    seq_.store(s + 1, std::memory_order_relaxed);  // odd: write in progress
    std::atomic_thread_fence(std::memory_order_release);
    CopyWords(value, words_);
    seq_.store(s + 2, std::memory_order_release);
  }

  // Any reader. False if nothing was published yet. Lock-free (retries only while a write overlaps).
  bool Read(T& out) const noexcept {
    std::uint64_t none = ~std::uint64_t{0};  // a version never reached: any published value is newer
    return ReadNewer(out, none);
  }

  // Any reader: the value if it is newer than `last_version` (the version of the value the reader holds), which is
  // then set to the copy's own version. The version comes from the same read as the copy (not a separate
  // version() call), so a write between the two can never hand the same value out twice. Lock-free.
  bool ReadNewer(T& out, std::uint64_t& last_version) const noexcept {
    for (;;) {
      const std::uint64_t s0 = seq_.load(std::memory_order_acquire);
      if (s0 == 0 || s0 / 2 == last_version) return false;  // nothing yet, or nothing newer complete
      if (s0 & 1) continue;
      T copy;
      LoadWords(words_, copy);
      std::atomic_thread_fence(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) == s0) {
        out = copy;
        last_version = s0 / 2;
        return true;
      }
    }
  }
  // How many values were published (readers use it to tell a new value from the one they hold).
  std::uint64_t version() const noexcept { return seq_.load(std::memory_order_acquire) / 2; }

 private:
  // The payload is stored as relaxed atomic words, so concurrent reads and writes are not a data race.
  static constexpr std::size_t kWords = (sizeof(T) + sizeof(std::uint64_t) - 1) / sizeof(std::uint64_t);
  static void CopyWords(const T& value, std::atomic<std::uint64_t>* words) noexcept {
    std::uint64_t buf[kWords] = {};
    std::memcpy(buf, static_cast<const void*>(&value), sizeof(T));
    for (std::size_t i = 0; i < kWords; ++i) words[i].store(buf[i], std::memory_order_relaxed);
  }
  static void LoadWords(const std::atomic<std::uint64_t>* words, T& value) noexcept {
    std::uint64_t buf[kWords];
    for (std::size_t i = 0; i < kWords; ++i) buf[i] = words[i].load(std::memory_order_relaxed);
    std::memcpy(static_cast<void*>(&value), buf, sizeof(T));
  }
  std::atomic<std::uint64_t> seq_{0};
  std::atomic<std::uint64_t> words_[kWords] = {};
};

}  // namespace robossis::rt
