// A real-time loop reading what a normal-priority thread publishes, beside the scheduler: the 1 kHz SCHED_FIFO 80
// loop (the leader's priority) reads an rt::Snapshot of a status-sized record that a SCHED_OTHER thread publishes back
// to back (as a link's receive thread publishes what arrives, here without pause, so that the loop's wake-up often
// preempts it in the middle of a publish). Both threads may run on any CPU; run it beside CPU-bound load.
//
// Arg 0: rt::Snapshot (a sequence latch: the reader takes the copy not being written). Arg 1, for comparison: a plain
// sequence lock (what rt::Snapshot was), whose reader spins while a write is in progress: when the loop preempted the
// writer on its CPU, it spun until the scheduler moved the writer elsewhere (the leader's stalls over DDS).
// Counters: the loop's longest tick, its overruns from ticks longer than one period (rt::LoopStats), and whether
// SCHED_FIFO was refused (then the figures mean nothing).

#include <array>
#include <atomic>
#include <cstdint>
#include <thread>
#include <tuple>

#include <benchmark/benchmark.h>

#include "src/core/rt/clock.h"
#include "src/core/rt/periodic_loop.h"
#include "src/core/rt/snapshot.h"

namespace robossis::rt {
namespace {

struct StatusSizedRecord {
  std::array<double, 40> values{};  // about a FollowerStatusMessage
};

// The baseline: a sequence lock over the same relaxed atomic words.
class SequenceLock {
 public:
  void Publish(const StatusSizedRecord& value) noexcept {
    const std::uint64_t s = seq_.load(std::memory_order_relaxed);
    seq_.store(s + 1, std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    for (std::size_t i = 0; i < kWords; ++i) words_[i].store(value.values[i], std::memory_order_relaxed);
    seq_.store(s + 2, std::memory_order_release);
  }
  bool ReadNewer(StatusSizedRecord& out, std::uint64_t& last_version) const noexcept {
    for (;;) {
      const std::uint64_t s0 = seq_.load(std::memory_order_acquire);
      if (s0 == 0 || s0 / 2 == last_version) return false;
      if (s0 & 1) continue;  // a write in progress: spin
      StatusSizedRecord copy;
      for (std::size_t i = 0; i < kWords; ++i) copy.values[i] = words_[i].load(std::memory_order_relaxed);
      std::atomic_thread_fence(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) == s0) {
        out = copy;
        last_version = s0 / 2;
        return true;
      }
    }
  }

 private:
  static constexpr std::size_t kWords = std::tuple_size_v<decltype(StatusSizedRecord::values)>;
  std::atomic<std::uint64_t> seq_{0};
  std::atomic<double> words_[kWords] = {};
};

template <typename Latest>
class LatestReader final : public PeriodicTask {
 public:
  explicit LatestReader(const Latest& latest) : latest_(latest) {}
  void Tick(std::int64_t) noexcept override {
    StatusSizedRecord r;
    if (latest_.ReadNewer(r, version_)) sum_ += r.values[0];
  }
  double sum() const noexcept { return sum_; }

 private:
  const Latest& latest_;
  std::uint64_t version_ = 0;
  double sum_ = 0;
};

template <typename Latest>
RunResult RunReaderBesideWriter(double duration_s) {
  MonotonicClock clock;
  Latest latest;
  std::atomic<bool> stop{false};
  std::thread writer([&] {
    StatusSizedRecord r;
    while (!stop.load(std::memory_order_relaxed)) {
      r.values[0] += 1;
      latest.Publish(r);
    }
  });
  LatestReader<Latest> reader(latest);
  RunResult run = RunRealTime(clock, {{&reader, {.name = "reader", .period_ns = 1'000'000}}}, duration_s, nullptr,
                              0.01, false);
  stop = true;
  writer.join();
  benchmark::DoNotOptimize(reader.sum());
  return run;
}

void BM_RealTimeReaderOfANormalPriorityWriter(benchmark::State& state) {
  const double duration_s = static_cast<double>(state.range(0));
  LoopStats stats;
  std::uint64_t refused = 0;
  for (auto _ : state) {
    const RunResult run = state.range(1) == 0 ? RunReaderBesideWriter<Snapshot<StatusSizedRecord>>(duration_s)
                                              : RunReaderBesideWriter<SequenceLock>(duration_s);
    refused += run.warnings.size();
    stats = run.stats[0];
  }
  state.counters["ticks"] = static_cast<double>(stats.ticks);
  state.counters["longest_tick_ms"] = 1e-3 * stats.tick_duration.max_us();
  state.counters["overruns_long_tick"] = static_cast<double>(stats.overruns_long_tick);
  state.counters["realtime_refused"] = static_cast<double>(refused);
}
BENCHMARK(BM_RealTimeReaderOfANormalPriorityWriter)
    ->Args({10, 0})
    ->Args({10, 1})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace robossis::rt
