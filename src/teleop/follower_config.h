#pragma once
// Settings of the follower unit, loaded once from data/config/follower.yaml and validated there. SI inside; the
// YAML keys carry their units. The speed caps come from transfer.yaml (transfer::SpeedCaps), the joint limits from
// rsr.yaml: the follower refers to them, it does not copy them.

#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "haptics/transfer/transfer_config.h"
#include "robot/feasible_motion.h"
#include "src/teleop/setpoint_validator.h"
#include "src/teleop/wrench_estimate.h"

namespace robossis {
class ConfigNode;
}  // namespace robossis

namespace robossis::teleop {

struct FollowerWatchdogConfig {
  double hold_after_s = 0.030;         // [assumed] no valid set-point this long -> hold
  double leader_lost_after_s = 0.5;    // [assumed] -> disabled
  double max_extrapolation_s = 0.002;  // [assumed]
  // The most motion one tick may command, in time at the caps ([assumed]): after a stalled tick (a loaded machine,
  // a page fault) the robot lags instead of jumping to where the caps would have taken it.
  double max_tick_interval_s = 0.001;
};

struct FollowerConfig {
  SetPointLimits setpoint;  // setpoint.caps are filled from transfer.yaml
  FollowerWatchdogConfig watchdog;
  double status_rate_hz = 1000;       // [assumed] >= 100 Hz
  std::size_t recorder_capacity = 65536;  // [assumed]
  robot::FeasibleMotionConfig guard;
  // ModelFingerprint of the rsr.yaml and actuation.yaml the model and the drives were loaded from
  // (TeleopSetup::Load), published with the status so that a leader on another machine can tell it checks against
  // another workspace or keeps within another robot's motor speeds. 0: not known.
  std::uint64_t model_fingerprint = 0;
  // The weight the wrench estimate removes: the back end's (the session sets it from the simulation's ring and
  // fragment; zero for back ends that do not say).
  WrenchEstimateConfig wrench;

  // Throws std::invalid_argument naming the field.
  void Validate() const;
  // Loads follower.yaml; `caps` are the transfer's (transfer.yaml). Throws std::runtime_error naming file and key.
  static FollowerConfig FromYaml(const std::filesystem::path& file, const transfer::SpeedCaps& caps);
  // The same from a document already loaded (ConfigNode::Load): one parse read by several loaders.
  static FollowerConfig FromConfig(const ConfigNode& root, const transfer::SpeedCaps& caps);
};

}  // namespace robossis::teleop
