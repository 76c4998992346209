#pragma once
// The flight recorder: every tick's inputs and outputs of both units into a session log (session_log.h) that
// survives a crash. The loops push their records into their own SpscQueues; a logger thread (not real-time) drains
// them every flush period, appends them to the log, hands the log to the kernel and passes each record on to
// whoever summarises the run. A killed process loses at most one flush period of records (default 2 ms) plus what
// sat in the queues.
//
// Streams: 0 "leader" (LeaderTickRecord), 1 "follower" (FollowerTickRecord, when the follower unit is recorded).

#include <atomic>
#include <functional>
#include <string>
#include <thread>

#include "src/teleop/leader_unit.h"
#include "src/teleop/session_log.h"

namespace robossis::teleop {

inline constexpr std::uint8_t kLeaderStream = 0;
inline constexpr std::uint8_t kFollowerStream = 1;

// The layout of LeaderTickRecord, for the log's header.
StreamSpec LeaderStreamSpec();

class FlightRecorder {
 public:
  // Drains the queues into the log (and on to consumers); called on the logger thread, then once more at Stop().
  using Drain = std::function<void(SessionLogWriter& log)>;

  FlightRecorder(SessionLogWriter& log, Drain drain, double flush_period_s = 0.002);
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
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::string error_;
};

}  // namespace robossis::teleop
