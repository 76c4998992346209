// The periodic loops: simulated stepping ticks every task at its own period, in the given order at shared
// instants, deterministically; the real-time runner ticks on absolute deadlines and counts; the histogram's
// percentiles; the loop bookkeeping allocates nothing per tick.

#include <atomic>
#include <vector>

#include <gtest/gtest.h>

#include "src/core/rt/periodic_loop.h"
#include "tests/support/alloc_counter.h"

namespace robossis::rt {
namespace {

class Recorder final : public PeriodicTask {
 public:
  Recorder(int id, std::vector<std::pair<int, std::int64_t>>* log) : id_(id), log_(log) {}
  void Tick(std::int64_t now_ns) noexcept override {
    ++ticks;
    if (log_ != nullptr) log_->emplace_back(id_, now_ns);
  }
  std::atomic<int> ticks{0};

 private:
  int id_;
  std::vector<std::pair<int, std::int64_t>>* log_;
};

TEST(PeriodicLoopTest, SimulatedRunTicksEachTaskAtItsPeriodInOrder) {
  std::vector<std::pair<int, std::int64_t>> log;
  log.reserve(1000);
  Recorder fast(0, &log), slow(1, &log);
  SimulatedClock clock;
  LoopOptions f, s;
  f.period_ns = 100'000;    // 10 kHz
  s.period_ns = 1'000'000;  // 1 kHz
  int background_calls = 0;
  const RunResult r = RunSimulated(clock, {{&fast, f}, {&slow, s}}, 0.005,
                                   [&](double) { ++background_calls; return true; }, 0.001);
  EXPECT_EQ(fast.ticks, 50);
  EXPECT_EQ(slow.ticks, 5);
  ASSERT_EQ(r.stats.size(), 2u);
  EXPECT_EQ(r.stats[0].ticks, 50u);
  EXPECT_EQ(r.stats[1].overruns, 0u);
  EXPECT_DOUBLE_EQ(r.elapsed_s, 0.005);
  EXPECT_EQ(clock.now_ns(), 5'000'000);
  EXPECT_GE(background_calls, 5);
  // At t = 0 and every 1 ms both are due: the fast task first (the order given), the slow one at the same time.
  ASSERT_GE(log.size(), 2u);
  EXPECT_EQ(log[0], std::make_pair(0, std::int64_t{0}));
  EXPECT_EQ(log[1], std::make_pair(1, std::int64_t{0}));
  for (const auto& [id, t] : log) EXPECT_EQ(t % (id == 0 ? f.period_ns : s.period_ns), 0);
}

TEST(PeriodicLoopTest, BackgroundCanStopASimulatedRunEarly) {
  Recorder task(0, nullptr);
  SimulatedClock clock;
  const RunResult r = RunSimulated(clock, {{&task, LoopOptions{}}}, 10.0, [](double now_s) { return now_s < 0.05; },
                                   0.01);
  EXPECT_TRUE(r.stopped_early);
  EXPECT_LT(task.ticks, 100);
  EXPECT_GT(task.ticks, 10);
}

TEST(PeriodicLoopTest, RealTimeRunTicksOnDeadlines) {
  Recorder task(0, nullptr);
  MonotonicClock clock;
  LoopOptions o;
  o.period_ns = 1'000'000;
  const RunResult r = RunRealTime(clock, {{&task, o}}, 0.05, nullptr, 0.01, /*lock_memory=*/false);
  ASSERT_EQ(r.stats.size(), 1u);
  EXPECT_GT(r.stats[0].ticks, 0u);
  EXPECT_EQ(r.stats[0].ticks, static_cast<std::uint64_t>(task.ticks.load()));
  EXPECT_EQ(r.stats[0].wake_latency.count(), r.stats[0].ticks);
  EXPECT_EQ(r.stats[0].period_jitter.count() + 1, r.stats[0].ticks);
  // Every deadline in the run was either ticked or counted as an overrun (ticks + overruns = the run's periods).
  EXPECT_LE(r.stats[0].ticks + r.stats[0].overruns, 60u);
}

TEST(LatencyHistogramTest, PercentilesAndOverflow) {
  LatencyHistogram h(100);
  for (int i = 0; i < 99; ++i) h.Add(5'500);  // 5.5 µs: bin 5, upper edge 6 µs
  h.Add(250'000);                              // 250 µs: overflow, exact max kept
  EXPECT_EQ(h.count(), 100u);
  EXPECT_DOUBLE_EQ(h.PercentileUs(0.5), 6.0);
  EXPECT_DOUBLE_EQ(h.PercentileUs(0.99), 6.0);
  EXPECT_DOUBLE_EQ(h.PercentileUs(1.0), 250.0);
  EXPECT_DOUBLE_EQ(h.max_us(), 250.0);
  testing::AllocationCounter counter;
  for (int i = 0; i < 1000; ++i) h.Add(i * 100);
  EXPECT_EQ(counter.count(), 0u);
}

}  // namespace
}  // namespace robossis::rt
