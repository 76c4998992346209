#include "robot/actuation/pulse_recorder_follower.h"

#include <stdexcept>

namespace robossis::actuation {

PulseRecorderFollower::PulseRecorderFollower(const robot::RsrModel& model, const ActuationConfig& config,
                                             const Eigen::Isometry3d& X_FM_start, std::size_t max_commands,
                                             std::size_t max_events)
    : model_(model) {
  const robot::RsrIkResult ik = robot::CalcInverseKinematics(model, X_FM_start);
  if (!ik.feasible) throw std::invalid_argument("pulse recorder: the start pose is outside the joint limits");
  q0_ = ik.joints.actuated();
  for (int m = 0; m < kNumMotors; ++m) pulses_[m] = PulseGenerator(config.motors[m].steps_per_unit);
  state_.q = q0_;
  state_.X_FM = X_FM_start;
  state_.homed = true;
  commands_.reserve(max_commands);
  events_.reserve(max_events);
}

bool PulseRecorderFollower::Enable() noexcept {
  if (state_.faulted()) return false;
  state_.enabled = true;
  return true;
}

bool PulseRecorderFollower::ResetFault() noexcept {
  if (fault_input_) return false;  // the cause is still there
  state_.fault = robot::FollowerFault::kNone;
  return true;
}

void PulseRecorderFollower::InjectFault(robot::FollowerFault fault) noexcept {
  fault_input_ = fault != robot::FollowerFault::kNone;
  if (fault_input_) {
    state_.fault = fault;
    state_.enabled = false;
  }
}

void PulseRecorderFollower::Command(const robot::RsrJointCommand& command) noexcept {
  if (!state_.enabled || !command.q.allFinite()) return;
  if (commands_.size() < commands_.capacity()) {
    commands_.push_back(command);  // within the reserved capacity: no allocation
  } else {
    ++dropped_;
  }
  // The ideal drive: the pulses of eq. 17 from the last serviced position to the command.
  std::array<StepEvent, kNumMotors * kMaxStepsPerTickPerMotor> tick_events{};
  int n = 0;
  for (int m = 0; m < kNumMotors; ++m) {
    n += pulses_[m].Advance(service_time_s_, command.time_s, command.q[m] - q0_[m], m, tick_events.data() + n,
                            kMaxStepsPerTickPerMotor);
  }
  for (int i = 0; i < n; ++i) {
    if (events_.size() < events_.capacity()) {
      events_.push_back(tick_events[i]);
    } else {
      ++dropped_;
    }
  }
  state_.q = command.q;
  const robot::RsrFkResult fk = robot::CalcForwardKinematics(model_, command.q, state_.X_FM);
  if (fk.converged()) state_.X_FM = fk.X_FM;
}

void PulseRecorderFollower::Service(double now_s) noexcept {
  service_time_s_ = now_s;
  state_.time_s = now_s;
  if (fault_input_) state_.enabled = false;
}

}  // namespace robossis::actuation
