#pragma once
// Timing statistics of a periodic loop, kept without allocation inside the loop: fixed 1 µs histogram bins (the
// storage is allocated once, at construction) for the wake-up latency (tick start − deadline, what cyclictest
// reports) and the period jitter (|start-to-start interval − nominal period|), plus overrun and tick counters.

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

struct LoopStats {
  std::int64_t period_ns = 0;
  std::uint64_t ticks = 0;
  std::uint64_t overruns = 0;       // deadlines missed: a tick (with its wake-up) ended after the next deadline
  LatencyHistogram wake_latency;    // tick start − its deadline
  LatencyHistogram period_jitter;   // |start − previous start − period|
  LatencyHistogram tick_duration;   // the task's own time per tick
  double overrun_rate() const noexcept { return ticks ? static_cast<double>(overruns) / static_cast<double>(ticks) : 0; }
};

}  // namespace robossis::rt
