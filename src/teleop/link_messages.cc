#include "src/teleop/link_messages.h"

namespace robossis::teleop {

const char* ToString(OperatingState state) {
  switch (state) {
    case OperatingState::kDisabled: return "disabled";
    case OperatingState::kHoming: return "homing";
    case OperatingState::kReady: return "ready";
    case OperatingState::kEnabled: return "enabled";
    case OperatingState::kClutched: return "clutched";
    case OperatingState::kFault: return "fault";
    case OperatingState::kEStop: return "estop";
  }
  return "unknown";
}

const char* ToString(StateCommand command) {
  switch (command) {
    case StateCommand::kEnable: return "enable";
    case StateCommand::kDisable: return "disable";
    case StateCommand::kHome: return "home";
    case StateCommand::kEStop: return "estop";
    case StateCommand::kReset: return "reset";
  }
  return "unknown";
}

const char* ToString(FaultReason reason) {
  switch (reason) {
    case FaultReason::kNone: return "none";
    case FaultReason::kBackEnd: return "back_end";
    case FaultReason::kDeviceFailure: return "device_failure";
    case FaultReason::kSetPointInvalid: return "setpoint_invalid";
    case FaultReason::kSetPointTooFast: return "setpoint_too_fast";
    case FaultReason::kLeaderLost: return "leader_lost";
    case FaultReason::kEStop: return "estop";
    case FaultReason::kNotHomed: return "not_homed";
  }
  return "unknown";
}

}  // namespace robossis::teleop
