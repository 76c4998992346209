#pragma once
// The flight recorder: every tick's inputs and outputs of both units into a session log (session_log.h) that
// survives a crash. The loops push their records into their own SpscQueues; a logger thread (not real-time) drains
// them every flush period, appends them to the log, hands the log to the kernel and passes each record on to
// whoever summarises the run. A killed process loses at most one flush period of records (default 2 ms) plus what
// sat in the queues. A drain or flush that throws ends the thread and sets the failure flag at once (the follower
// holds: a motion is never left unrecorded); Stop() returns the error.
//
// Streams: 0 "leader" (LeaderTickRecord), 1 "follower" (FollowerTickRecord, when the follower unit is recorded).

#include <atomic>
#include <functional>
#include <string>
#include <thread>

#include "src/teleop/follower_unit.h"
#include "src/teleop/leader_unit.h"
#include "src/teleop/session_log.h"

namespace robossis::teleop {

inline constexpr std::uint8_t kLeaderStream = 0;
inline constexpr std::uint8_t kFollowerStream = 1;
inline constexpr std::uint8_t kEndStream = 2;

// What only the end of a run knows: the loops' own timing statistics and the units' counters. One record, written
// last; a log without it is from a run that did not end (a crash).
// Overruns are split by cause (rt::OverrunCause): a late wake-up (scheduling) or a tick longer than its period.
struct SessionEndRecord {
  double elapsed_s = 0;
  std::uint64_t leader_loop_ticks = 0;
  std::uint64_t leader_overruns = 0;
  std::uint64_t leader_overruns_late_wake = 0;
  std::uint64_t leader_overruns_long_tick = 0;
  double leader_period_jitter_us_p99 = 0;
  double leader_period_jitter_us_max = 0;
  double leader_wake_latency_us_p99 = 0;
  std::uint64_t follower_loop_ticks = 0;
  std::uint64_t follower_overruns = 0;
  std::uint64_t follower_overruns_late_wake = 0;
  std::uint64_t follower_overruns_long_tick = 0;
  double follower_period_jitter_us_p99 = 0;
  double follower_period_jitter_us_max = 0;
  double follower_wake_latency_us_p99 = 0;
  std::uint64_t watchdog_holds = 0;
  std::uint64_t setpoints_accepted = 0;
  std::uint64_t setpoints_rejected = 0;
  std::uint64_t leader_records_dropped = 0;
  std::uint64_t follower_records_dropped = 0;
  std::uint64_t device_failures = 0;
  std::uint64_t ik_rejected = 0;
  // The simulated robot's own loop (robot::Follower::plant()), when the back end runs one; zero otherwise.
  std::uint64_t plant_loop_ticks = 0;
  std::uint64_t plant_overruns = 0;
  std::uint64_t plant_overruns_late_wake = 0;
  std::uint64_t plant_overruns_long_tick = 0;
};

// The layouts, for the log's header.
StreamSpec LeaderStreamSpec();
StreamSpec FollowerStreamSpec();
StreamSpec EndStreamSpec();

class FlightRecorder {
 public:
  // Drains the queues into the log (and on to consumers); called on the logger thread, then once more at Stop().
  using Drain = std::function<void(SessionLogWriter& log)>;

  // `failed` (may be null) is set when the drain or a flush throws: the follower unit watching it holds the robot.
  FlightRecorder(SessionLogWriter& log, Drain drain, double flush_period_s = 0.002,
                 std::atomic<bool>* failed = nullptr);
  ~FlightRecorder();
  FlightRecorder(const FlightRecorder&) = delete;
  FlightRecorder& operator=(const FlightRecorder&) = delete;

  void Start();
  // Stops the thread, drains what is left and flushes. Returns the thread's error ("" if none).
  std::string Stop();

 private:
  void Run();
  SessionLogWriter& log_;
  Drain drain_;
  double flush_period_s_;
  std::atomic<bool>* failed_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::string error_;
};

}  // namespace robossis::teleop
