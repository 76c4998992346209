#pragma once
// What the panel shows, computed from one follower status snapshot: the pose in mm and degrees, the state and the
// last fault's reason, and per joint a gauge of its value between its limits with the margin (inverse kinematics
// eq. 5–8 of the measured pose). Pure functions of the snapshot: testable without a window.

#include <array>
#include <string>

#include <Eigen/Geometry>

#include "robot/rsr_kinematics.h"
#include "robot/rsr_model.h"
#include "src/teleop/link_messages.h"

namespace robossis::panel {

struct JointGauge {
  std::string label;   // "arm 1 stroke"
  const char* unit = "mm";
  double value = 0;    // in `unit`
  double lower = 0;    // the range the gauge spans, in `unit`
  double upper = 0;
  double margin = 0;   // to the nearest limit, in `unit` (< 0: violated)
  // Where the value sits in [lower, upper], clamped to [0, 1].
  double fraction() const;
};

struct PanelViewModel {
  bool has_status = false;
  Eigen::Isometry3d X_FM = Eigen::Isometry3d::Identity();
  std::array<double, 6> pose_mm_deg{};  // x, y, z (mm), roll, pitch, yaw (deg)
  teleop::OperatingState state = teleop::OperatingState::kDisabled;
  std::string state_name;
  std::string fault_text;               // "" when no fault is latched
  std::string refusal_text;             // why the follower refused the last enable; "" when it did not
  bool latched = false;                 // E-stop or fault: a reset is needed
  bool homed = false;                   // the follower's joints are referenced
  // The Home button makes sense only on a disabled follower: a latched one needs a reset first, a homing one is on
  // its way, a powered one is homed (and is not re-referenced while it holds or moves).
  bool home_allowed = false;
  std::array<JointGauge, 9> gauges{};   // per arm: rotary, stroke, spherical cone
  bool feasible = true;
};

Eigen::Isometry3d PoseOf(const teleop::FollowerStatusMessage& status);
PanelViewModel BuildViewModel(const robot::RsrModel& model, const teleop::FollowerStatusMessage& status);

}  // namespace robossis::panel
