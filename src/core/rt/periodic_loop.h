#pragma once
// Periodic loops: one thread per unit on absolute deadlines (clock_nanosleep on CLOCK_MONOTONIC, TIMER_ABSTIME, so
// a late tick does not shift the ones after it), SCHED_FIFO and mlockall where the process is permitted (a warning
// names what was refused, and the loop runs anyway at normal priority), overruns and period jitter counted.
//
// Missed deadlines are skipped, never made up: after a late tick (a stall, a preemption) the next tick is the first
// deadline still ahead, and each deadline missed counts as an overrun, under its cause (rt::OverrunCause: a late
// wake-up, or a tick longer than its period; LoopStats::AccountTick). A control tick acts on the present (it reads
// the clock and bounds its motion by the time that really passed), so a burst of ticks would only hand the drives a
// run of commands meant for instants already gone. A task whose model needs every step (the simulated robot's
// physics) makes them up inside its one late tick, with the commands at their own times (sim::SimulatedPlant).
//
// The same tasks run either on threads in real time (RunRealTime, on a MonotonicClock) or stepped
// deterministically on a SimulatedClock as fast as the machine allows (RunSimulated): each task is ticked at its own
// period, tasks due at the same instant in the order given. The non-real-time side runs in the calling thread
// (`background`, every background_period_s), and reaches the loops only through src/core/rt structures.

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "src/core/rt/clock.h"
#include "src/core/rt/loop_stats.h"
#include "src/core/rt/periodic_task.h"
#include "src/core/rt/snapshot.h"

namespace robossis::rt {

// SCHED_FIFO priorities of the runtime's loops, where permitted [assumed]: below the kernel's IRQ threads (50) is
// wrong for a servo loop; 80 leaves room above for a watchdog. The actuation outranks the haptic loop: a late
// stepper command is a jerk of the robot, a late haptic tick a softer wall for one tick.
inline constexpr int kHapticLoopFifoPriority = 80;
inline constexpr int kActuationLoopFifoPriority = 81;
// A simulated robot's own loop (the plant a back end runs beside the controller) yields to both: it stands for
// hardware that would not share the controller's CPU [assumed].
inline constexpr int kPlantLoopFifoPriority = 79;

// The threads that carry set-points and status between the loops (a DDS link end's send and receive threads, and
// Cyclone DDS's receive, delivery and event threads) [assumed]: below every loop, above normal-priority work, so that
// a busy machine does not hold the set-points back past the follower's watchdog (30 ms).
inline constexpr int kLinkThreadFifoPriority = 70;

// Puts `thread` on SCHED_FIFO at `priority`. Returns the error text ("" on success); the thread keeps its policy
// when refused.
std::string SetFifoPriority(std::thread& thread, int priority);
// Whether this process may run a thread at SCHED_FIFO `priority` (the calling thread tries it and goes back).
bool FifoPermitted(int priority);

struct LoopOptions {
  std::string name = "loop";
  std::int64_t period_ns = 1'000'000;
  int fifo_priority = kHapticLoopFifoPriority;
  bool try_realtime = true;    // attempt SCHED_FIFO
};

// The loop of a robot simulated beside the controller (robot::Follower::plant()): its own period, the plant's priority.
inline LoopOptions PlantLoopOptions(std::int64_t period_ns, std::string name = "plant") {
  return {.name = std::move(name), .period_ns = period_ns, .fifo_priority = kPlantLoopFifoPriority};
}

// One thread ticking one task on absolute deadlines.
class PeriodicLoop {
 public:
  PeriodicLoop(const MonotonicClock& clock, PeriodicTask& task, const LoopOptions& options);
  ~PeriodicLoop();
  PeriodicLoop(const PeriodicLoop&) = delete;
  PeriodicLoop& operator=(const PeriodicLoop&) = delete;

  // Starts the thread; the first deadline is start_ns on the clock (ns since its epoch). Returns a warning (empty if
  // none): SCHED_FIFO refused.
  std::string Start(std::int64_t start_ns);
  void Stop() noexcept;  // requests the stop and joins
  // Safe to read once stopped; counts() (the stats' counters after the last tick, overruns by cause) at any time.
  const LoopStats& stats() const noexcept { return stats_; }
  LoopCounts counts() const noexcept {
    LoopCounts c;
    counts_.Read(c);
    return c;
  }
  const LoopOptions& options() const noexcept { return options_; }

 private:
  void Run(std::int64_t start_ns) noexcept;
  const MonotonicClock& clock_;
  PeriodicTask& task_;
  LoopOptions options_;
  LoopStats stats_;
  std::atomic<bool> stop_{false};
  Snapshot<LoopCounts> counts_;
  std::thread thread_;
};

// Locks the process's memory (mlockall, current and future pages) so a tick never waits for a page fault. Returns
// a warning (empty if it worked).
std::string LockMemory();

struct ScheduledTask {
  PeriodicTask* task = nullptr;
  LoopOptions options;
};

struct RunResult {
  std::vector<LoopStats> stats;        // one per task, in the order given
  std::vector<std::string> warnings;   // what real-time setup was refused
  double elapsed_s = 0;                // run time on the run's clock
  bool stopped_early = false;          // `background` asked to stop before the duration
};

// `background` is called from the calling thread about every background_period_s of the run's clock (and once at
// the end); returning false stops the run early. It may allocate and print; it must not touch the tasks except
// through rt structures.
using BackgroundWork = std::function<bool(double now_s)>;

// Real time: a thread per task, started together, for duration_s of wall-clock time.
RunResult RunRealTime(const MonotonicClock& clock, const std::vector<ScheduledTask>& tasks, double duration_s,
                      const BackgroundWork& background, double background_period_s = 0.01, bool lock_memory = true);

// Simulated time: ticks every task at its period on `clock` (advanced here), from the clock's current time for
// duration_s. Deterministic.
RunResult RunSimulated(SimulatedClock& clock, const std::vector<ScheduledTask>& tasks, double duration_s,
                       const BackgroundWork& background, double background_period_s = 0.01);

}  // namespace robossis::rt
