#include "src/teleop/in_process_link.h"

#include <cmath>
#include <stdexcept>

namespace robossis::teleop {

InProcessLink::InProcessLink(const rt::Clock& clock, std::size_t command_capacity, double one_way_delay_s,
                             std::size_t delay_capacity)
    : clock_(clock),
      delayed_(one_way_delay_s > 0),
      setpoint_delay_(std::llround(one_way_delay_s * 1e9), delayed_ ? delay_capacity : 1),
      status_delay_(std::llround(one_way_delay_s * 1e9), delayed_ ? delay_capacity : 1),
      leader_commands_(command_capacity),
      operator_commands_(command_capacity) {
  if (!(std::isfinite(one_way_delay_s) && one_way_delay_s >= 0 && one_way_delay_s <= 10)) {
    throw std::invalid_argument("in-process link: the one-way delay must be 0 to 10 s");
  }
}

std::int64_t InProcessLink::NowNs() const noexcept {
  return static_cast<std::int64_t>(std::llround(clock_.NowS() * 1e9));
}

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
  if (delayed_) {
    setpoint_delay_.Send(message, NowNs());
    return;
  }
  TimedSetPoint t;
  t.message = message;
  t.arrival_ns = NowNs();
  setpoint_.Publish(t);
}

bool InProcessLink::TakeFollowerStatus(FollowerStatusMessage& message) noexcept {
  if (delayed_) {
    std::int64_t due_ns = 0;
    return status_delay_.Take(NowNs(), message, due_ns);
  }
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
  if (delayed_) return setpoint_delay_.Take(NowNs(), message, arrival_ns);
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

void InProcessLink::PublishStatus(const FollowerStatusMessage& message) noexcept {
  status_.Publish(message);
  if (delayed_) status_delay_.Send(message, NowNs());
}

}  // namespace robossis::teleop
