#include "src/teleop/in_process_link.h"

#include <cmath>

namespace robossis::teleop {

InProcessLink::InProcessLink(const rt::Clock& clock, std::size_t command_capacity)
    : clock_(clock), leader_commands_(command_capacity), operator_commands_(command_capacity) {}

bool OperatorCommandPort::Send(const StateCommandMessage& message) noexcept {
  if (message.command == StateCommand::kEStop) {
    SendEStop();
    return true;
  }
  if (link_.operator_commands_.TryPush(message)) return true;
  link_.commands_dropped_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

void OperatorCommandPort::SendEStop() noexcept { link_.SendEStop(); }

void InProcessLink::SendSetPoint(const SetPointMessage& message) noexcept {
  TimedSetPoint t;
  t.message = message;
  t.arrival_ns = static_cast<std::int64_t>(std::llround(clock_.NowS() * 1e9));
  setpoint_.Publish(t);
}

bool InProcessLink::TakeFollowerStatus(FollowerStatusMessage& message) noexcept {
  return status_.ReadNewer(message, status_taken_version_);
}

bool InProcessLink::SendCommand(const StateCommandMessage& message) noexcept {
  if (message.command == StateCommand::kEStop) {
    SendEStop();
    return true;
  }
  if (leader_commands_.TryPush(message)) return true;
  commands_dropped_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

bool InProcessLink::TakeSetPoint(SetPointMessage& message, std::int64_t& arrival_ns) noexcept {
  TimedSetPoint t;
  if (!setpoint_.ReadNewer(t, setpoint_taken_version_)) return false;
  message = t.message;
  arrival_ns = t.arrival_ns;
  return true;
}

bool InProcessLink::TakeCommand(StateCommandMessage& message) noexcept {
  // The leader's queue first, then the operator's; both are drained every tick (the E-stop is not queued at all).
  if (leader_commands_.TryPop(message)) return true;
  return operator_commands_.TryPop(message);
}

void InProcessLink::PublishStatus(const FollowerStatusMessage& message) noexcept { status_.Publish(message); }

}  // namespace robossis::teleop
