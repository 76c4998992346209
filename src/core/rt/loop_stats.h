#pragma once
// Timing statistics of a periodic loop, kept without allocation inside the loop: fixed 1 µs histogram bins (the
// storage is allocated once, at construction) for the wake-up latency (tick start − deadline, what cyclictest
// reports) and the period jitter (|start-to-start interval − nominal period|), plus tick counters and the overruns
// by cause.

#include <cstdint>
#include <vector>

namespace robossis::rt {

class LatencyHistogram {
 public:
  // Bins of 1 µs from 0 to max_us; anything longer falls in the overflow bin (its exact maximum is kept).
  explicit LatencyHistogram(int max_us = 10000) : bins_(static_cast<std::size_t>(max_us) + 1, 0) {}

  void Add(std::int64_t ns) noexcept {
    if (ns < 0) ns = 0;
    const std::int64_t us = ns / 1000;
    const std::size_t last = bins_.size() - 1;
    ++bins_[us < static_cast<std::int64_t>(last) ? static_cast<std::size_t>(us) : last];
    ++count_;
    sum_ns_ += static_cast<double>(ns);
    if (ns > max_ns_) max_ns_ = ns;
  }

  std::uint64_t count() const noexcept { return count_; }
  double max_us() const noexcept { return 1e-3 * static_cast<double>(max_ns_); }
  double mean_us() const noexcept { return count_ ? 1e-3 * sum_ns_ / static_cast<double>(count_) : 0.0; }
  // The upper edge of the bin holding the p-th fraction (0..1) of the samples, in µs (0 if empty); the exact
  // maximum when that bin is the overflow bin.
  double PercentileUs(double p) const noexcept;
  const std::vector<std::uint64_t>& bins() const noexcept { return bins_; }

 private:
  std::vector<std::uint64_t> bins_;
  std::uint64_t count_ = 0;
  double sum_ns_ = 0;
  std::int64_t max_ns_ = 0;
};

// Why a tick missed deadlines. Each tick that ends after the next deadline is counted under one cause, by what
// would have happened had it started on time:
//   kLateWake  the tick's own duration fits in the period, so it would have met the deadline had the loop woken
//              on time: the wake-up was late (scheduling: the thread was not run at its deadline);
//   kLongTick  the tick's own duration (start to end, on the loop's clock) passed the period: it would have missed
//              even on time. On a real clock that duration includes any preemption in the middle of the tick.
enum class OverrunCause { kLateWake, kLongTick };
inline OverrunCause CauseOfOverrun(std::int64_t tick_duration_ns, std::int64_t period_ns) noexcept {
  return tick_duration_ns > period_ns ? OverrunCause::kLongTick : OverrunCause::kLateWake;
}

// A loop's counters as one consistent value: what a panel or a benchmark shows while the loop runs.
struct LoopCounts {
  std::uint64_t ticks = 0;
  std::uint64_t overruns = 0;
  std::uint64_t overruns_late_wake = 0;  // by cause (OverrunCause): overruns_late_wake + overruns_long_tick == overruns
  std::uint64_t overruns_long_tick = 0;
};

struct LoopStats {
  std::int64_t period_ns = 0;
  std::uint64_t ticks = 0;
  std::uint64_t overruns = 0;       // deadlines missed: a tick (with its wake-up) ended after the next deadline
  // overruns split by cause (OverrunCause): overruns_late_wake + overruns_long_tick == overruns.
  std::uint64_t overruns_late_wake = 0;
  std::uint64_t overruns_long_tick = 0;
  LatencyHistogram wake_latency;    // tick start − its deadline
  LatencyHistogram period_jitter;   // |start − previous start − period|
  LatencyHistogram tick_duration;   // the task's own time per tick
  std::int64_t previous_start_ns = -1;  // the last tick's start (for the jitter), -1 before the first

  LoopCounts counts() const noexcept { return {ticks, overruns, overruns_late_wake, overruns_long_tick}; }
  double overrun_rate() const noexcept { return ticks ? static_cast<double>(overruns) / static_cast<double>(ticks) : 0; }

  // Accounts one tick that was due at deadline_ns, started at start_ns and ended at end_ns (the loop's clock, ns),
  // and returns the next deadline. Missed deadlines are skipped, never made up (src/core/rt/periodic_loop.h): the
  // next deadline is the first one after end_ns, and each skipped one counts as an overrun of this tick's cause.
  std::int64_t AccountTick(std::int64_t deadline_ns, std::int64_t start_ns, std::int64_t end_ns) noexcept {
    wake_latency.Add(start_ns - deadline_ns);
    if (previous_start_ns >= 0) {
      const std::int64_t interval = start_ns - previous_start_ns - period_ns;
      period_jitter.Add(interval < 0 ? -interval : interval);
    }
    previous_start_ns = start_ns;
    const std::int64_t duration = end_ns - start_ns;
    tick_duration.Add(duration);
    ++ticks;
    std::int64_t next = deadline_ns + period_ns;
    if (end_ns > next) {
      const std::int64_t missed = (end_ns - next) / period_ns + 1;
      overruns += static_cast<std::uint64_t>(missed);
      const bool long_tick = CauseOfOverrun(duration, period_ns) == OverrunCause::kLongTick;
      (long_tick ? overruns_long_tick : overruns_late_wake) += static_cast<std::uint64_t>(missed);
      next += missed * period_ns;
    }
    return next;
  }
};

}  // namespace robossis::rt
