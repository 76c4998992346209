#pragma once
// A follower back end that records the pulse schedule (timestamps per motor) and the joint commands, for the CLI,
// the demo and the tests. Not real-time: it appends to vectors (reserve() first to keep a loop allocation-free).

#include <vector>

#include "robot/actuation/actuator.h"

namespace robossis::actuation {

class PulseRecorder {
 public:
  void Reserve(std::size_t events, std::size_t commands) {
    events_.reserve(events);
    commands_.reserve(commands);
  }
  void Record(const ActuationOutput& output) {
    events_.insert(events_.end(), output.events.begin(), output.events.begin() + output.num_events);
    commands_.push_back(output.command);
  }
  const std::vector<StepEvent>& events() const { return events_; }
  const std::vector<robot::RsrJointCommand>& commands() const { return commands_; }

 private:
  std::vector<StepEvent> events_;
  std::vector<robot::RsrJointCommand> commands_;
};

}  // namespace robossis::actuation
