#pragma once
// The communication channel of Fig. 2, as each unit sees it. The leader and follower units talk only through these
// two interfaces, so the same units run in one process (teleop::InProcessLink, lock-free snapshots and queues) or
// in two processes on two machines (link::DdsLeaderLink / link::DdsFollowerLink over Cyclone DDS).
//
// Real-time calls (noexcept, allocation-free, lock-free, never block): everything the loops call each tick.
// "Latest" semantics for set-points and status (a newer value replaces an unread older one, as best-effort
// keep-last-1 does on the wire); commands are queued (a full queue drops and counts). The E-stop is not a queued
// command but a latched level (EStopLatch): engaging it never fails and nothing queued before it delays or drops
// it; the old kEStop state command is routed to the same level by every link.

#include <cstdint>

#include "src/teleop/link_messages.h"

namespace robossis::teleop {

class LeaderLink {
 public:
  virtual ~LeaderLink() = default;
  virtual void SendSetPoint(const SetPointMessage& message) noexcept = 0;
  // The newest follower status not yet taken; false if none arrived since the last call.
  virtual bool TakeFollowerStatus(FollowerStatusMessage& message) noexcept = 0;
  // A state command to the follower. Over DDS only the panel's credentials grant it (a leader's link refuses it:
  // false); the leader unit sends none. False if the link refused it.
  virtual bool SendCommand(const StateCommandMessage& message) noexcept = 0;
  // Engages the E-stop (the leader on a device failure, the panel's button, the command line). Never refused by a
  // full queue; the follower leaves the E-stop only by an explicit reset.
  virtual void SendEStop() noexcept = 0;
};

class FollowerLink {
 public:
  virtual ~FollowerLink() = default;
  // The newest set-point not yet taken; false if none arrived since the last call. `arrival_ns` is the follower's
  // clock at arrival (ns), from which the follower judges freshness.
  virtual bool TakeSetPoint(SetPointMessage& message, std::int64_t& arrival_ns) noexcept = 0;
  // The next queued command from any participant; false when none is waiting.
  virtual bool TakeCommand(StateCommandMessage& message) noexcept = 0;
  virtual void PublishStatus(const FollowerStatusMessage& message) noexcept = 0;
  // How many E-stops were engaged so far (only ever grows): the follower E-stops whenever it has grown.
  virtual std::uint64_t EStopsEngaged() const noexcept = 0;
  // What the link adds to a status's stamp (the follower's clock) on the way out, the same for the link's whole
  // life: 0 in one process; over DDS the system clock's offset from the follower's clock, so that the headers
  // carry the system time of the status. A status's stamp as received minus this is the follower's clock again:
  // the session log keeps it, so that the leader's log and the follower's join on one time base.
  virtual std::int64_t StatusStampOffsetNs() const noexcept { return 0; }
};

}  // namespace robossis::teleop
