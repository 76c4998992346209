#pragma once
// A follower link with a local command port: the commands of the follower's own machine (its command line: the
// enable at start, a local E-stop) merged with the commands that arrive over the link. Set-points and status pass
// straight through to the wrapped link.
//
// Producers: exactly one local thread calls SendLocal(); the follower unit is the one consumer. A local kEStop (or
// SendLocalEStop(), from any thread) engages a local E-stop level instead of queueing, so it is never dropped; the
// E-stops engaged are the local ones plus the wrapped link's. Every call is allocation-free, lock-free and
// noexcept; the queue is allocated at construction.

#include <atomic>
#include <cstdint>

#include "src/core/rt/spsc_queue.h"
#include "src/teleop/estop_latch.h"
#include "src/teleop/link.h"

namespace robossis::teleop {

class LocalCommandLink final : public FollowerLink {
 public:
  // `link` must outlive this object.
  explicit LocalCommandLink(FollowerLink& link, std::size_t command_capacity = 16) : link_(link), local_(command_capacity) {}

  // The local producer's end (one thread). False if the queue was full (the command is dropped and counted).
  bool SendLocal(const StateCommandMessage& message) noexcept {
    if (message.command == StateCommand::kEStop) {
      SendLocalEStop();
      return true;
    }
    if (local_.TryPush(message)) return true;
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  void SendLocalEStop() noexcept { estop_.Engage(); }
  std::uint64_t local_commands_dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }

  bool TakeSetPoint(SetPointMessage& message, std::int64_t& arrival_ns) noexcept override {
    return link_.TakeSetPoint(message, arrival_ns);
  }
  // Local commands first: the machine's own commands are not queued behind the network's.
  bool TakeCommand(StateCommandMessage& message) noexcept override {
    return local_.TryPop(message) || link_.TakeCommand(message);
  }
  void PublishStatus(const FollowerStatusMessage& message) noexcept override { link_.PublishStatus(message); }
  std::uint64_t EStopsEngaged() const noexcept override { return estop_.engaged() + link_.EStopsEngaged(); }
  std::int64_t StatusStampOffsetNs() const noexcept override { return link_.StatusStampOffsetNs(); }

 private:
  FollowerLink& link_;
  rt::SpscQueue<StateCommandMessage> local_;
  std::atomic<std::uint64_t> dropped_{0};
  EStopLatch estop_;
};

}  // namespace robossis::teleop
