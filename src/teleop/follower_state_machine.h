#pragma once
// The follower's safety state machine, patterned on dVRK's: disabled, homing, ready, enabled, clutched, fault,
// E-stop. It owns the back end's life cycle (Enable/Disable/Home/ResetFault) and decides, tick by tick, whether the
// robot may follow the set-points.
//
//   disabled --home--> homing (until the back end is homed) --> disabled (homed)
//   disabled --enable, homed--> ready (drives on, holding)     disabled --enable, unhomed--> refused (kNotHomed)
//   homing --enable--> homing, then ready once homed (the operator's "home, then enable")
//   ready --presence + a valid set-point--> enabled        enabled --no presence--> ready
//   enabled --clutch open--> clutched --clutch closed--> enabled (re-anchored by the unit)
//   any --back-end fault--> fault (latched with its reason)       any --estop--> estop (latched)
//   fault/estop --reset--> disabled (a fault only once the back end clears it)   any --disable--> disabled
//   enabled/ready/clutched --leader lost--> disabled (reason kept)
//
// Homing is only ever the explicit home command: an enable never homes. A back end that does not measure its joints
// (open-loop step/direction drives) takes Home() as the operator's declaration that the robot stands at its home
// pose; homing it as a side effect of enable would re-reference a robot restarted wherever it stood.
//
// Real time: every call is allocation-free and noexcept.

#include <cstdint>

#include "robot/follower.h"
#include "src/teleop/link_messages.h"

namespace robossis::teleop {

// What the unit observed this tick.
struct FollowerInputs {
  bool presence = false;        // the newest valid set-point's presence flag
  bool clutched = false;        // the newest valid set-point's clutch flag
  bool have_valid_setpoint = false;  // a valid set-point newer than the watchdog's hold time
  bool leader_lost = false;     // no valid set-point for longer than the leader timeout
};

class FollowerStateMachine {
 public:
  OperatingState state() const noexcept { return state_; }
  // Why the last fault, E-stop, forced disable or refused enable (kNotHomed) happened (kNone after a reset from a
  // clean state, or a home).
  FaultReason reason() const noexcept { return reason_; }
  robot::FollowerFault back_end_fault() const noexcept { return back_end_fault_; }
  std::uint64_t transitions() const noexcept { return transitions_; }
  // True in the states in which the robot follows set-points.
  bool following() const noexcept { return state_ == OperatingState::kEnabled; }
  // True if the drives should be powered (holding or following).
  bool powered() const noexcept {
    return state_ == OperatingState::kReady || state_ == OperatingState::kEnabled ||
           state_ == OperatingState::kClutched;
  }

  // A command from any participant. Returns false if it was refused in this state (the state is unchanged).
  bool OnCommand(StateCommand command, robot::Follower& back_end) noexcept;
  // Once per tick, after the commands: the back end's condition and the set-point's flags.
  void Update(const FollowerInputs& inputs, robot::Follower& back_end) noexcept;
  // A fault raised by the unit itself (for example a set-point it cannot use).
  void RaiseFault(FaultReason reason, robot::Follower& back_end) noexcept;

 private:
  void Enter(OperatingState next) noexcept;
  bool OnHome(robot::Follower& back_end) noexcept;
  bool OnEnable(robot::Follower& back_end) noexcept;
  OperatingState state_ = OperatingState::kDisabled;
  FaultReason reason_ = FaultReason::kNone;
  robot::FollowerFault back_end_fault_ = robot::FollowerFault::kNone;
  bool enable_after_homing_ = false;  // an enable arrived while homing: enable once homed
  std::uint64_t transitions_ = 0;
};

}  // namespace robossis::teleop
