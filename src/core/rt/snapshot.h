#pragma once
// The latest value of a record, published by one writer and read by any number of readers without locks or waiting
// (a sequence latch: two copies, so that a reader always has a complete one). The writer never waits; a reader never
// waits for the writer either: a writer stopped anywhere (preempted, or a normal-priority thread held off its CPU by
// the very real-time reader that wants its value) leaves the previous value readable, and a reader copies again
// only when the writer has made progress during its copy. How the panel, the logger and the other unit read a
// loop's state, and a real-time loop reads what a non-real-time thread (a link's receive thread) writes.
//
// Why not a plain sequence lock: its reader retries for as long as a write is in progress. A SCHED_FIFO reader that
// preempts a SCHED_OTHER writer in the middle of a write on the same CPU then spins until the scheduler moves the
// writer to another CPU or throttles the real-time class (up to sched_rt_runtime_us, 0.95 s a second): the leader's
// loop over DDS stalled this way reading the follower's status (tick of 242 ms measured; bench_rt reproduces it).

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
  // Writer only. Wait-free, allocation-free. The sequence's parity steers readers to the copy not being written:
  // odd while copy 0 is written (readers take copy 1, the previous value), even while copy 1 is (readers take copy
  // 0, the new value).
  void Publish(const T& value) noexcept {
    BeginPublish(value);
    EndPublish(value);
  }

  // Any reader. False if nothing was published yet. Wait-free while the writer is stopped.
  bool Read(T& out) const noexcept {
    std::uint64_t none = ~std::uint64_t{0};  // a version never reached: any published value is newer
    return ReadNewer(out, none);
  }

  // Any reader: the value if it is newer than `last_version` (the version of the value the reader holds), which is
  // then set to the copy's own version. The version comes from the same read as the copy (not a separate
  // version() call), so a write between the two can never hand the same value out twice. Copies again only if the
  // writer moved on during the copy.
  bool ReadNewer(T& out, std::uint64_t& last_version) const noexcept {
    for (;;) {
      const std::uint64_t s0 = seq_.load(std::memory_order_acquire);
      const std::uint64_t version = s0 / 2;  // complete values in the copy readers take now
      if (version == 0 || version == last_version) return false;  // nothing yet, or nothing newer complete
      T copy;
      LoadWords(words_[s0 & 1], copy);
      std::atomic_thread_fence(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) == s0) {
        out = copy;
        last_version = version;
        return true;
      }
    }
  }
  // How many values were published (readers use it to tell a new value from the one they hold).
  std::uint64_t version() const noexcept { return seq_.load(std::memory_order_acquire) / 2; }

 private:
  friend class SnapshotTestAccess;  // stops a writer between the halves (tests/core/rt_test.cc)
  // The first half: copy 0 takes the value while readers take copy 1.
  void BeginPublish(const T& value) noexcept {
    // Release: the last write of copy 1 (which readers now take) before the odd sequence.
    seq_.store(seq_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
    std::atomic_thread_fence(std::memory_order_release);  // the odd sequence before any word of copy 0
    CopyWords(value, words_[0]);
  }
  // The second half: readers move to copy 0 (release: after its last word), then copy 1 takes the value too.
  void EndPublish(const T& value) noexcept {
    seq_.store(seq_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
    std::atomic_thread_fence(std::memory_order_release);  // the even sequence before any word of copy 1
    CopyWords(value, words_[1]);
  }

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
  std::atomic<std::uint64_t> seq_{0};  // 2 × the values published, + 1 while the first half of a write runs
  std::atomic<std::uint64_t> words_[2][kWords] = {};
};

}  // namespace robossis::rt
