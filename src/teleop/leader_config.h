#pragma once
// Configuration of the leader unit: data/config/leader.yaml. Loaded and validated once; the loop only reads it.

#include <cstddef>
#include <cstdint>
#include <string>
#include <filesystem>
#include <limits>

#include "haptics/device/device_factory.h"
#include "haptics/device/haptic_device.h"
#include "robot/feasible_motion.h"
#include "src/teleop/feedback_passivity.h"
#include "src/teleop/let_go_detector.h"

namespace robossis {
class ConfigNode;
}  // namespace robossis

namespace robossis::teleop {

// What the hand feels: the walls alone (the paper), or the walls and the follower's load (bilateral).
enum class FeedbackMode : std::uint8_t { kWalls, kBilateral };
const char* ToString(FeedbackMode mode);
// "walls" or "bilateral"; throws std::invalid_argument naming `where` and the value.
FeedbackMode ParseFeedbackMode(const char* where, const std::string& value);

// The follower's load on the hand (leader.yaml `feedback`).
struct LeaderFeedbackConfig {
  FeedbackMode mode = FeedbackMode::kWalls;
  // [assumed] The share of the follower's wrench the hand feels (after the transfer's scaling, inverted): 0.025
  // brings the paper's 517 N traction to 12.9 N, within the 15 N cap.
  double gain = 0.025;
  // The displayed wall + feedback wrench's caps: the rendering's (haptics.yaml `limits`, copied by
  // TeleopSetup::Load), below the device's own.
  double max_force_n = 15.0;
  double max_torque_nm = 0.3;
  FeedbackPassivityConfig passivity;
  // The let-go detector (let_go_detector.h; `robossis teleop --let-go-detector`): once it believes the operator let
  // go, the load is no longer shown and the device is damped to rest, until the presence or the clutch is taken anew.
  bool detect_let_go = false;
  LetGoConfig let_go;
  void Validate() const;  // throws std::invalid_argument naming the field
};

struct LeaderConfig {
  double rate_hz = 1000;                     // the haptic loop
  haptics::DeviceLimits device;              // the device's own limits, applied by HapticDevice
  int boundary_bisection_steps = 14;         // the wire-rounding fallback: bisection toward the last set-point
  robot::FeasibleMotionConfig guard;         // the feasible-motion guard's tuning (its defaults)
  // The follower's acceleration caps (follower.yaml `setpoint`, copied by TeleopSetup::Load: one place for each
  // limit). The leader's set-points move within them and within the transfer's speed caps, so that the follower's
  // validator accepts every one, at a wall too.
  double max_linear_accel_m_s2 = 5.0;
  double max_angular_accel_rad_s2 = 10.0;
  // The follower's motors' top speeds (rad/s rotary, m/s linear, eq. 13 order; actuation.yaml's step rates over
  // their resolutions, copied by TeleopSetup::Load). The set-points move no faster than the motors can follow: a
  // hand too fast for the motors is slowed at the leader, as the speed caps slow it, and the follower need not
  // shorten its steps and fall behind what it was sent. Infinite: no bound.
  robot::RsrJointVector max_joint_speed = robot::RsrJointVector::Constant(std::numeric_limits<double>::infinity());
  double motor_speed_share = 0.9;  // of max_joint_speed the set-points keep within ([assumed], leader.yaml)
  // A follower status older than this means the link or the follower is gone: the leader stops rendering the
  // robot's motion ([assumed], leader.yaml; the follower publishes at 1 kHz).
  double follower_status_timeout_s = 0.1;
  std::size_t record_queue_capacity = 16384; // leader records waiting for the flight recorder
  haptics::DeviceScriptOptions sim_script;   // the `sim` device's hand
  LeaderFeedbackConfig feedback;

  // Throws std::invalid_argument naming the field.
  void Validate() const;
  // Throws std::runtime_error naming the file and key.
  static LeaderConfig FromYaml(const std::filesystem::path& file);
  // The same from a document already loaded (ConfigNode::Load): one parse read by several loaders.
  static LeaderConfig FromConfig(const ConfigNode& root);
};

}  // namespace robossis::teleop
