#pragma once
// The names the follower's HAL component and the HAL files share: its pins (<component>.joint.N.pos-cmd, ...) and
// the signals the HAL files create for them (<component>-jN-pos-cmd, ...). The component links each pin to its
// signal when it starts, so a HAL file can be loaded before the follower runs. Joints are in eq. 13 order.

#include <string>

namespace robossis::drivers {

enum class JointPin {
  kPosCmd,  // out: commanded joint displacement from the homing reference (rad or m)
  kVelCmd,  // out: its velocity feed-forward, eq. 15 (rad/s or m/s)
  kPosFb,   // in: measured displacement (stepgen's position-fb, or an encoder)
  kEnable,  // out: this drive powered and following
};
inline constexpr JointPin kJointPins[] = {JointPin::kPosCmd, JointPin::kVelCmd, JointPin::kPosFb, JointPin::kEnable};

enum class UnitPin {
  kFault,         // in: an external fault (E-stop chain, card watchdog); raised = FollowerFault::kExternal
  kWatchdog,      // out: heartbeat, toggled once the echo shows the last level; HAL's watchdog watches it
  kWatchdogEcho,  // in: the watchdog inverted by the servo thread; frozen = lost feedback
  kEnabled,       // out: the follower is enabled (arms HAL's watchdog)
};
inline constexpr UnitPin kUnitPins[] = {UnitPin::kFault, UnitPin::kWatchdog, UnitPin::kWatchdogEcho,
                                        UnitPin::kEnabled};

inline const char* Suffix(JointPin pin) {
  switch (pin) {
    case JointPin::kPosCmd: return "pos-cmd";
    case JointPin::kVelCmd: return "vel-cmd";
    case JointPin::kPosFb: return "pos-fb";
    case JointPin::kEnable: return "enable";
  }
  return "?";
}

inline const char* Suffix(UnitPin pin) {
  switch (pin) {
    case UnitPin::kFault: return "fault";
    case UnitPin::kWatchdog: return "watchdog";
    case UnitPin::kWatchdogEcho: return "watchdog-echo";
    case UnitPin::kEnabled: return "enabled";
  }
  return "?";
}

inline std::string PinName(const std::string& component, int joint, JointPin pin) {
  return component + ".joint." + std::to_string(joint) + "." + Suffix(pin);
}
inline std::string PinName(const std::string& component, UnitPin pin) { return component + "." + Suffix(pin); }
inline std::string SignalName(const std::string& component, int joint, JointPin pin) {
  return component + "-j" + std::to_string(joint) + "-" + Suffix(pin);
}
inline std::string SignalName(const std::string& component, UnitPin pin) { return component + "-" + Suffix(pin); }

}  // namespace robossis::drivers
