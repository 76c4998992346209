#include "src/teleop/follower_state_machine.h"

namespace robossis::teleop {

void FollowerStateMachine::Enter(OperatingState next) noexcept {
  if (next != state_) ++transitions_;
  if (next != OperatingState::kHoming) enable_after_homing_ = false;  // a pending enable dies with the homing
  state_ = next;
}

bool FollowerStateMachine::OnHome(robot::Follower& back_end) noexcept {
  if (state_ == OperatingState::kHoming) return true;
  // Only a disabled robot is referenced: a powered one is already homed (and referencing a moving robot is
  // meaningless); the latched states need a reset first.
  if (state_ != OperatingState::kDisabled) return false;
  reason_ = FaultReason::kNone;
  // A back end that cannot reference yet (the HAL drives before their first feedback) is asked again each tick.
  if (!back_end.Home() || !back_end.State().homed) Enter(OperatingState::kHoming);
  return true;
}

bool FollowerStateMachine::OnEnable(robot::Follower& back_end) noexcept {
  if (state_ == OperatingState::kHoming) {
    enable_after_homing_ = true;  // the operator homed, then enabled: enable once the homing is done
    return true;
  }
  // Already on: an enable is idempotent; latched states refuse it.
  if (state_ != OperatingState::kDisabled) return powered();
  if (!back_end.State().homed) {
    reason_ = FaultReason::kNotHomed;  // refused, and never homed here: homing is the operator's explicit action
    return false;
  }
  reason_ = FaultReason::kNone;
  if (!back_end.Enable()) return false;
  Enter(OperatingState::kReady);
  return true;
}

bool FollowerStateMachine::OnCommand(StateCommand command, robot::Follower& back_end) noexcept {
  switch (command) {
    case StateCommand::kEStop:
      back_end.Disable();
      reason_ = FaultReason::kEStop;
      Enter(OperatingState::kEStop);
      return true;
    case StateCommand::kReset:
      if (state_ == OperatingState::kEStop) {
        // The E-stop is released by an explicit reset only; the drives stay off until the next enable.
        if (back_end.State().faulted() && !back_end.ResetFault()) return false;
        reason_ = FaultReason::kNone;
        back_end_fault_ = robot::FollowerFault::kNone;
        Enter(OperatingState::kDisabled);
        return true;
      }
      if (state_ == OperatingState::kFault) {
        if (back_end.State().faulted() && !back_end.ResetFault()) return false;  // the cause is still there
        reason_ = FaultReason::kNone;
        back_end_fault_ = robot::FollowerFault::kNone;
        Enter(OperatingState::kDisabled);
        return true;
      }
      return state_ == OperatingState::kDisabled;  // nothing to reset
    case StateCommand::kDisable:
      if (state_ == OperatingState::kEStop || state_ == OperatingState::kFault) return false;  // latched
      back_end.Disable();
      Enter(OperatingState::kDisabled);
      return true;
    case StateCommand::kHome:
      return OnHome(back_end);
    case StateCommand::kEnable:
      return OnEnable(back_end);
  }
  return false;
}

void FollowerStateMachine::RaiseFault(FaultReason reason, robot::Follower& back_end) noexcept {
  if (state_ == OperatingState::kEStop) return;  // the E-stop stays the latched state
  back_end.Disable();
  reason_ = reason;
  Enter(OperatingState::kFault);
}

void FollowerStateMachine::Update(const FollowerInputs& in, robot::Follower& back_end) noexcept {
  const robot::RsrFollowerState be = back_end.State();
  if (be.faulted() && state_ != OperatingState::kEStop && state_ != OperatingState::kFault) {
    back_end_fault_ = be.fault;
    RaiseFault(FaultReason::kBackEnd, back_end);
    return;
  }
  switch (state_) {
    case OperatingState::kHoming:
      if (!be.homed) back_end.Home();
      if (!back_end.State().homed) return;
      if (!enable_after_homing_) {
        Enter(OperatingState::kDisabled);
      } else if (back_end.Enable()) {
        Enter(OperatingState::kReady);
      } else {
        back_end_fault_ = be.fault;
        RaiseFault(FaultReason::kBackEnd, back_end);
      }
      return;
    case OperatingState::kReady:
    case OperatingState::kEnabled:
    case OperatingState::kClutched:
      if (in.leader_lost) {
        back_end.Disable();
        reason_ = FaultReason::kLeaderLost;
        Enter(OperatingState::kDisabled);
        return;
      }
      if (!be.enabled) {  // the drives dropped out without a fault code: treat it as a drive fault
        back_end_fault_ = robot::FollowerFault::kDrive;
        RaiseFault(FaultReason::kBackEnd, back_end);
        return;
      }
      if (!in.presence || !in.have_valid_setpoint) {
        Enter(OperatingState::kReady);  // no motion without presence and a live leader: hold
      } else if (in.clutched) {
        Enter(OperatingState::kClutched);
      } else {
        Enter(OperatingState::kEnabled);
      }
      return;
    case OperatingState::kDisabled:
    case OperatingState::kFault:
    case OperatingState::kEStop:
      return;
  }
}

}  // namespace robossis::teleop
