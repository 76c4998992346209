#pragma once
// The pulse recorder as a follower back end: an ideal drive that follows every joint command exactly and records
// the commands and the step/direction pulses (eq. 17, one PulseGenerator per motor, the same as the actuator's)
// into storage allocated at construction. Real time: every robot::Follower call is allocation-free and noexcept;
// when the storage is full the newest entries are dropped and counted. For `robossis teleop --follower recorder`,
// the tests, and as the template of a hardware back end.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "robot/actuation/actuation_config.h"
#include "robot/actuation/pulse_generator.h"
#include "robot/follower.h"

namespace robossis::actuation {

class PulseRecorderFollower final : public robot::Follower {
 public:
  // The motors' zero is IK(X_FM_start) (as the actuator's). Throws std::invalid_argument if the start pose is
  // outside the joint limits.
  PulseRecorderFollower(const robot::RsrModel& model, const ActuationConfig& config,
                        const Eigen::Isometry3d& X_FM_start, std::size_t max_commands, std::size_t max_events);

  bool Enable() noexcept override;
  void Disable() noexcept override { state_.enabled = false; }
  bool Home() noexcept override { return true; }  // the command is the position: referenced from the start
  bool MeasuresJoints() const noexcept override { return true; }
  bool ResetFault() noexcept override;
  void Command(const robot::RsrJointCommand& command) noexcept override;
  void Service(double now_s) noexcept override;
  robot::RsrFollowerState State() const noexcept override { return state_; }

  // An external fault input (the tests' stand-in for a drive's fault line).
  void InjectFault(robot::FollowerFault fault) noexcept;

  const std::vector<robot::RsrJointCommand>& commands() const noexcept { return commands_; }
  const std::vector<StepEvent>& events() const noexcept { return events_; }
  std::size_t dropped() const noexcept { return dropped_; }
  std::int64_t steps(int motor) const noexcept { return pulses_[motor].steps(); }

 private:
  const robot::RsrModel& model_;
  robot::RsrJointVector q0_;
  std::array<PulseGenerator, kNumMotors> pulses_;
  robot::RsrFollowerState state_;
  bool fault_input_ = false;
  double service_time_s_ = 0;
  std::vector<robot::RsrJointCommand> commands_;
  std::vector<StepEvent> events_;
  std::size_t dropped_ = 0;
};

}  // namespace robossis::actuation
