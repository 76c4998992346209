// The periodic loops: simulated stepping ticks every task at its own period, in the given order at shared
// instants, deterministically; the real-time runner ticks on absolute deadlines and accounts for every deadline,
// ticked or skipped (bookkeeping that holds however the machine is loaded; its timing is the benchmarks'); the
// histogram's percentiles; each missed deadline counted under its cause, on a fake clock; the loop bookkeeping
// allocates nothing per tick.

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

// Only what holds however the threads are scheduled: how many ticks fit in the run depends on the machine's load,
// so the run lasts until the task has ticked a few times (a generous bound, not a timing), and the checks are the
// bookkeeping: every tick counted and timed, no tick before its deadline, and every deadline between the first and
// the last tick either ticked or counted as an overrun. Tick timing itself is measured by the benchmarks.
TEST(PeriodicLoopTest, RealTimeRunTicksOnDeadlines) {
  struct Stamps final : PeriodicTask {
    void Tick(std::int64_t now_ns) noexcept override {
      if (ticks.load() == 0) first_ns = now_ns;
      last_ns = now_ns;
      ticks.fetch_add(1);
    }
    std::atomic<int> ticks{0};
    std::int64_t first_ns = -1;  // written by the loop's thread, read after the run joined it
    std::int64_t last_ns = -1;
  } task;
  MonotonicClock clock;
  LoopOptions o;
  o.period_ns = 1'000'000;
  const std::int64_t before_ns = MonotonicNowNs() - clock.epoch_ns();
  constexpr int kEnoughTicks = 20;
  const RunResult r = RunRealTime(clock, {{&task, o}}, /*duration_s=*/60.0,
                                  [&](double) { return task.ticks.load() < kEnoughTicks; }, 0.01,
                                  /*lock_memory=*/false);
  ASSERT_TRUE(r.stopped_early) << "the loop ticked " << task.ticks.load() << " times in 60 s";
  ASSERT_EQ(r.stats.size(), 1u);
  const LoopStats& s = r.stats[0];
  EXPECT_GE(s.ticks, static_cast<std::uint64_t>(kEnoughTicks));
  EXPECT_EQ(s.ticks, static_cast<std::uint64_t>(task.ticks.load()));
  EXPECT_EQ(s.wake_latency.count(), s.ticks);
  EXPECT_EQ(s.period_jitter.count() + 1, s.ticks);
  EXPECT_EQ(s.tick_duration.count(), s.ticks);
  // The first deadline is ahead of the call, and the first tick does not start before it.
  EXPECT_GT(task.first_ns, before_ns);
  // Deadlines are period apart from the first (k = 0, 1, ...), each either ticked or skipped and counted as an
  // overrun. The deadline after the last tick, number ticks + overruns, is not before that tick's end, ...
  const std::uint64_t deadlines = s.ticks + s.overruns;
  EXPECT_GE(static_cast<double>(deadlines) * o.period_ns, static_cast<double>(task.last_ns - task.first_ns))
      << s.ticks << " ticks, " << s.overruns << " overruns: skipped deadlines were not counted";
  // ... and it is the first one after that tick's end, which came before the run ended (elapsed_s counts from the
  // first deadline to after the loop stopped): at most one deadline is counted beyond the run.
  EXPECT_LE(static_cast<double>(deadlines - 1) * o.period_ns, r.elapsed_s * 1e9 + 1.0)
      << s.ticks << " ticks, " << s.overruns << " overruns in " << r.elapsed_s << " s";
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

// The loop's bookkeeping on a fake clock (times in ns given by the test): each overrun is counted under its own
// cause, whatever the machine.
class OverrunCauseTest : public ::testing::Test {
 protected:
  OverrunCauseTest() { stats.period_ns = kPeriod; }
  static constexpr std::int64_t kPeriod = 100'000;  // 10 kHz
  LoopStats stats;
};

TEST_F(OverrunCauseTest, ATickThatEndsBeforeTheNextDeadlineIsNoOverrun) {
  // Woke 30 µs late, worked 60 µs: ends at 90 µs, before the next deadline (100 µs).
  EXPECT_EQ(stats.AccountTick(0, 30'000, 90'000), kPeriod);
  EXPECT_EQ(stats.overruns, 0u);
  EXPECT_EQ(stats.ticks, 1u);
}

TEST_F(OverrunCauseTest, ALateWakeIsCountedAsALateWake) {
  // Woke 250 µs late, then a 10 µs tick: on time it would have fit. Deadlines 100, 200 µs skipped (ends at 260 µs),
  // the next one is 300 µs.
  EXPECT_EQ(stats.AccountTick(0, 250'000, 260'000), 3 * kPeriod);
  EXPECT_EQ(stats.overruns, 2u);
  EXPECT_EQ(stats.overruns_late_wake, 2u);
  EXPECT_EQ(stats.overruns_long_tick, 0u);
}

TEST_F(OverrunCauseTest, ALateWakeThatLeavesTooLittleOfThePeriodIsALateWake) {
  // Woke 50 µs late, a 60 µs tick (within the period): it ends at 110 µs because it started late.
  EXPECT_EQ(stats.AccountTick(0, 50'000, 110'000), 2 * kPeriod);
  EXPECT_EQ(stats.overruns_late_wake, 1u);
  EXPECT_EQ(stats.overruns_long_tick, 0u);
}

TEST_F(OverrunCauseTest, ALongTickIsCountedAsALongTick) {
  // On time, but the tick itself took 120 µs: the deadline at 100 µs is missed, the next one is 200 µs.
  EXPECT_EQ(stats.AccountTick(0, 0, 120'000), 2 * kPeriod);
  EXPECT_EQ(stats.overruns, 1u);
  EXPECT_EQ(stats.overruns_long_tick, 1u);
  EXPECT_EQ(stats.overruns_late_wake, 0u);
  // A 100 ms stall inside a tick (a page fault, a preemption in the middle of the work): 1000 deadlines missed.
  EXPECT_EQ(stats.AccountTick(2 * kPeriod, 2 * kPeriod, 2 * kPeriod + 100'000'000), 1003 * kPeriod);
  EXPECT_EQ(stats.overruns_long_tick, 1u + 1000u);
  EXPECT_EQ(stats.overruns_late_wake, 0u);
}

TEST_F(OverrunCauseTest, TheCausesAddUpToTheOverrunsOverAMixedRun) {
  std::int64_t deadline = 0;
  deadline = stats.AccountTick(deadline, deadline, deadline + 10'000);             // on time
  deadline = stats.AccountTick(deadline, deadline + 150'000, deadline + 160'000);  // late wake: 1 missed
  deadline = stats.AccountTick(deadline, deadline, deadline + 230'000);            // long tick: 2 missed
  deadline = stats.AccountTick(deadline, deadline + 5'000, deadline + 15'000);     // on time
  EXPECT_EQ(stats.ticks, 4u);
  EXPECT_EQ(stats.overruns_late_wake, 1u);
  EXPECT_EQ(stats.overruns_long_tick, 2u);
  EXPECT_EQ(stats.overruns, 3u);
  // Every deadline is either ticked or skipped: 4 ticks + 3 skipped, the next is the 8th.
  EXPECT_EQ(deadline, 7 * kPeriod);
  EXPECT_EQ(stats.wake_latency.count(), 4u);
  EXPECT_EQ(stats.period_jitter.count(), 3u);
}

TEST_F(OverrunCauseTest, TheBookkeepingAllocatesNothing) {
  testing::AllocationCounter counter;
  std::int64_t deadline = 0;
  for (int i = 0; i < 1000; ++i) {
    deadline = stats.AccountTick(deadline, deadline + (i % 7) * 40'000, deadline + (i % 5) * 50'000 + 300'000);
  }
  EXPECT_EQ(counter.count(), 0u);
}

}  // namespace
}  // namespace robossis::rt
