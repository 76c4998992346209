#pragma once
// Both ends of the link in one process: the leader unit and the follower unit (and the command line or the panel)
// on threads of the same program. Set-points and status are "latest" values (rt::Snapshot, as best-effort
// keep-last-1 on the wire); commands are queued per producer (one rt::SpscQueue each, never lost unless full).
// Arrival time is the shared clock's reading when the set-point was sent, plus the link's one-way delay: with a
// delay (`robossis teleop --link-delay-ms`) both directions go through a DelayLine, each message arriving that much
// later at its reader (watchers reading the status directly see it undelayed, as at the follower).
//
// Producers: the leader unit sends set-points and leader commands; exactly one other thread (the command line or
// the panel) sends operator commands through operator_commands(). The follower unit is the one consumer. The E-stop
// is a latched level (EStopLatch) that any thread may engage, through SendEStop(), the operator port's SendEStop(),
// or a kEStop command on either port: it is never queued, so a full queue cannot drop it.
// Every call is allocation-free, lock-free and noexcept; the queues are allocated at construction.

#include <atomic>
#include <cstdint>

#include "src/core/rt/clock.h"
#include "src/core/rt/snapshot.h"
#include "src/core/rt/spsc_queue.h"
#include "src/teleop/delay_line.h"
#include "src/teleop/estop_latch.h"
#include "src/teleop/link.h"

namespace robossis::teleop {

class InProcessLink;

// A set-point with its arrival time on the shared clock.
struct TimedSetPoint {
  SetPointMessage message;
  std::int64_t arrival_ns = 0;
};

// The operator's (command line or panel) way to send state commands: a second producer with its own queue.
class OperatorCommandPort {
 public:
  explicit OperatorCommandPort(InProcessLink& link) noexcept : link_(link) {}
  // A kEStop command engages the E-stop level (never refused); others are queued (false if the queue was full).
  bool Send(const StateCommandMessage& message) noexcept;
  void SendEStop() noexcept;

 private:
  InProcessLink& link_;
};

class InProcessLink final : public LeaderLink, public FollowerLink {
 public:
  // one_way_delay_s: both directions' delay (0: none); the delay lines hold up to delay_capacity messages each.
  explicit InProcessLink(const rt::Clock& clock, std::size_t command_capacity = 64, double one_way_delay_s = 0,
                         std::size_t delay_capacity = 4096);

  // LeaderLink
  void SendSetPoint(const SetPointMessage& message) noexcept override;
  bool TakeFollowerStatus(FollowerStatusMessage& message) noexcept override;
  bool SendCommand(const StateCommandMessage& message) noexcept override;
  void SendEStop() noexcept override { estop_.Engage(); }
  // FollowerLink
  bool TakeSetPoint(SetPointMessage& message, std::int64_t& arrival_ns) noexcept override;
  bool TakeCommand(StateCommandMessage& message) noexcept override;
  void PublishStatus(const FollowerStatusMessage& message) noexcept override;
  std::uint64_t EStopsEngaged() const noexcept override { return estop_.engaged(); }

  // The operator's command producer (one thread).
  OperatorCommandPort& operator_commands() noexcept { return operator_port_; }
  // The newest status, for any number of watchers (the panel, the logger), without taking it from the leader.
  bool ReadFollowerStatus(FollowerStatusMessage& message) const noexcept { return status_.Read(message); }
  std::uint64_t commands_dropped() const noexcept { return commands_dropped_.load(std::memory_order_relaxed); }
  double one_way_delay_s() const noexcept { return 1e-9 * static_cast<double>(setpoint_delay_.delay_ns()); }
  // Messages a delay line had no room for (a delay longer than its capacity at the sending rate).
  std::uint64_t delayed_dropped() const noexcept { return setpoint_delay_.dropped() + status_delay_.dropped(); }

 private:
  friend class OperatorCommandPort;
  const rt::Clock& clock_;
  std::int64_t NowNs() const noexcept;
  bool delayed_;
  DelayLine<SetPointMessage> setpoint_delay_;
  DelayLine<FollowerStatusMessage> status_delay_;
  rt::Snapshot<TimedSetPoint> setpoint_;
  std::uint64_t setpoint_taken_version_ = 0;  // follower side
  rt::Snapshot<FollowerStatusMessage> status_;
  std::uint64_t status_taken_version_ = 0;    // leader side
  rt::SpscQueue<StateCommandMessage> leader_commands_;
  rt::SpscQueue<StateCommandMessage> operator_commands_;
  OperatorCommandPort operator_port_{*this};
  std::atomic<std::uint64_t> commands_dropped_{0};
  EStopLatch estop_;
};

}  // namespace robossis::teleop
