#include "src/core/rt/periodic_loop.h"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <ctime>
#include <numeric>

namespace robossis::rt {

double LatencyHistogram::PercentileUs(double p) const noexcept {
  if (count_ == 0) return 0;
  const double target = std::clamp(p, 0.0, 1.0) * static_cast<double>(count_);
  std::uint64_t seen = 0;
  for (std::size_t i = 0; i < bins_.size(); ++i) {
    seen += bins_[i];
    if (static_cast<double>(seen) >= target && seen > 0) {
      return i + 1 == bins_.size() ? max_us() : std::min(static_cast<double>(i + 1), max_us());
    }
  }
  return max_us();
}

namespace {

void SleepUntil(std::int64_t abs_ns) noexcept {
  timespec ts;
  ts.tv_sec = static_cast<time_t>(abs_ns / 1'000'000'000);
  ts.tv_nsec = static_cast<long>(abs_ns % 1'000'000'000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

}  // namespace

PeriodicLoop::PeriodicLoop(const MonotonicClock& clock, PeriodicTask& task, const LoopOptions& options)
    : clock_(clock), task_(task), options_(options) {
  stats_.period_ns = options.period_ns;
}

PeriodicLoop::~PeriodicLoop() { Stop(); }

std::string SetFifoPriority(std::thread& thread, int priority) {
  sched_param param{};
  param.sched_priority = priority;
  const int err = pthread_setschedparam(thread.native_handle(), SCHED_FIFO, &param);
  return err == 0 ? std::string() : std::strerror(err);
}

bool FifoPermitted(int priority) {
  // The calling thread tries, then goes back to its own policy (lowering is always permitted).
  int policy = SCHED_OTHER;
  sched_param own{};
  if (pthread_getschedparam(pthread_self(), &policy, &own) != 0) return false;
  sched_param param{};
  param.sched_priority = priority;
  if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) != 0) return false;
  pthread_setschedparam(pthread_self(), policy, &own);
  return true;
}

std::string PeriodicLoop::Start(std::int64_t start_ns) {
  stop_.store(false);
  thread_ = std::thread([this, start_ns] { Run(start_ns); });
  if (!options_.try_realtime) return {};
  const std::string error = SetFifoPriority(thread_, options_.fifo_priority);
  if (error.empty()) return {};
  return options_.name + ": SCHED_FIFO priority " + std::to_string(options_.fifo_priority) + " refused (" + error +
         "); running at normal priority, expect larger jitter (grant CAP_SYS_NICE or an rtprio limit)";
}

void PeriodicLoop::Stop() noexcept {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
}

void PeriodicLoop::Run(std::int64_t start_ns) noexcept {
  const std::int64_t epoch = clock_.epoch_ns();
  std::int64_t deadline = start_ns;
  while (!stop_.load(std::memory_order_relaxed)) {
    SleepUntil(epoch + deadline);
    const std::int64_t start = MonotonicNowNs() - epoch;
    task_.Tick(start);
    const std::int64_t end = MonotonicNowNs() - epoch;
    // Missed deadlines are skipped, not made up: the next tick is the first deadline still ahead.
    deadline = stats_.AccountTick(deadline, start, end);
    counts_.Publish(stats_.counts());
  }
}

std::string LockMemory() {
  if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) return {};
  return std::string("mlockall refused (") + std::strerror(errno) +
         "); memory is not locked, a page fault may delay a tick (raise the memlock limit)";
}

RunResult RunRealTime(const MonotonicClock& clock, const std::vector<ScheduledTask>& tasks, double duration_s,
                      const BackgroundWork& background, double background_period_s, bool lock_memory) {
  RunResult result;
  if (lock_memory) {
    if (std::string w = LockMemory(); !w.empty()) result.warnings.push_back(std::move(w));
  }
  std::vector<std::unique_ptr<PeriodicLoop>> loops;
  for (const ScheduledTask& t : tasks) loops.push_back(std::make_unique<PeriodicLoop>(clock, *t.task, t.options));
  // All loops start at the same deadline, a little ahead so that every thread is up by then.
  const std::int64_t start_ns = MonotonicNowNs() - clock.epoch_ns() + 5'000'000;
  for (auto& loop : loops) {
    if (std::string w = loop->Start(start_ns); !w.empty()) result.warnings.push_back(std::move(w));
  }
  const std::int64_t end_ns = start_ns + static_cast<std::int64_t>(std::llround(duration_s * 1e9));
  const std::int64_t step_ns = std::max<std::int64_t>(1'000'000, std::llround(background_period_s * 1e9));
  std::int64_t next = start_ns + step_ns;
  while (next < end_ns) {
    SleepUntil(clock.epoch_ns() + next);
    if (background && !background(1e-9 * static_cast<double>(next))) {
      result.stopped_early = true;
      break;
    }
    next += step_ns;
  }
  if (!result.stopped_early) SleepUntil(clock.epoch_ns() + end_ns);
  for (auto& loop : loops) loop->Stop();
  result.elapsed_s = 1e-9 * static_cast<double>(MonotonicNowNs() - clock.epoch_ns() - start_ns);
  if (background) background(clock.NowS());
  for (auto& loop : loops) result.stats.push_back(loop->stats());
  return result;
}

RunResult RunSimulated(SimulatedClock& clock, const std::vector<ScheduledTask>& tasks, double duration_s,
                       const BackgroundWork& background, double background_period_s) {
  RunResult result;
  const std::size_t n = tasks.size();
  std::vector<std::int64_t> next(n, clock.now_ns());
  for (std::size_t i = 0; i < n; ++i) {
    LoopStats s;
    s.period_ns = tasks[i].options.period_ns;
    result.stats.push_back(std::move(s));
  }
  const std::int64_t start_ns = clock.now_ns();
  const std::int64_t end_ns = start_ns + static_cast<std::int64_t>(std::llround(duration_s * 1e9));
  const std::int64_t step_ns = std::max<std::int64_t>(1, std::llround(background_period_s * 1e9));
  std::int64_t next_background = start_ns + step_ns;
  for (;;) {
    const std::int64_t t = n ? *std::min_element(next.begin(), next.end()) : end_ns;
    if (t >= end_ns) break;
    if (t >= next_background) {
      clock.SetNs(next_background);
      next_background += step_ns;
      if (background && !background(clock.NowS())) {
        result.stopped_early = true;
        break;
      }
      continue;
    }
    clock.SetNs(t);
    for (std::size_t i = 0; i < n; ++i) {
      if (next[i] != t) continue;
      tasks[i].task->Tick(t);
      // Simulated time: every tick starts on its deadline and takes no time.
      next[i] = result.stats[i].AccountTick(t, t, t);
    }
  }
  if (!result.stopped_early) clock.SetNs(end_ns);
  result.elapsed_s = 1e-9 * static_cast<double>(clock.now_ns() - start_ns);
  if (background) background(clock.NowS());
  return result;
}

}  // namespace robossis::rt
