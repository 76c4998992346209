#include "src/panel/view_model.h"

#include <algorithm>

#include "robot/follower.h"
#include "src/core/pose.h"
#include "src/core/units.h"

namespace robossis::panel {

double JointGauge::fraction() const {
  if (!(upper > lower)) return 0;
  return std::clamp((value - lower) / (upper - lower), 0.0, 1.0);
}

Eigen::Isometry3d PoseOf(const teleop::FollowerStatusMessage& status) {
  const Eigen::Quaterniond q(status.q_FM[0], status.q_FM[1], status.q_FM[2], status.q_FM[3]);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = q.normalized().toRotationMatrix();
  X.translation() = Eigen::Vector3d(status.p_FM[0], status.p_FM[1], status.p_FM[2]);
  return X;
}

PanelViewModel BuildViewModel(const robot::RsrModel& model, const teleop::FollowerStatusMessage& status) {
  PanelViewModel view;
  view.has_status = true;
  view.X_FM = PoseOf(status);
  const Vector6d mm_deg = MmDegFromPose(view.X_FM);
  for (int i = 0; i < 6; ++i) view.pose_mm_deg[i] = mm_deg[i];
  view.state = status.state;
  view.state_name = teleop::ToString(status.state);
  view.latched = status.state == teleop::OperatingState::kFault || status.state == teleop::OperatingState::kEStop;
  view.homed = status.homed;
  view.home_allowed = status.state == teleop::OperatingState::kDisabled;
  if (status.fault_reason == teleop::FaultReason::kNotHomed) {
    view.refusal_text = "enable refused: not homed (Home with the robot at its home pose, then Enable)";
  } else if (status.fault_reason != teleop::FaultReason::kNone) {
    view.fault_text = teleop::ToString(status.fault_reason);
    if (status.fault_reason == teleop::FaultReason::kBackEnd)
      view.fault_text += std::string(": ") + robot::ToString(static_cast<robot::FollowerFault>(status.back_end_fault));
  }

  const robot::RsrIkResult ik = robot::CalcInverseKinematics(model, view.X_FM);  // eq. 5–8
  view.feasible = ik.feasible;
  const robot::RsrLimits& limits = model.limits();
  for (int arm = 0; arm < robot::kNumArms; ++arm) {
    const std::string name = "arm " + std::to_string(arm + 1);
    JointGauge& rotary = view.gauges[3 * arm + 0];
    rotary.label = name + " rotary";
    rotary.unit = "deg";
    rotary.value = RadToDeg(ik.joints.theta_rad[arm]);
    rotary.lower = -RadToDeg(limits.rotary_max_rad);
    rotary.upper = RadToDeg(limits.rotary_max_rad);
    JointGauge& stroke = view.gauges[3 * arm + 1];
    stroke.label = name + " stroke";
    stroke.unit = "mm";
    stroke.value = MToMm(ik.joints.d_m[arm]);
    stroke.lower = MToMm(limits.stroke_min_m);
    stroke.upper = MToMm(limits.stroke_max_m);
    JointGauge& cone = view.gauges[3 * arm + 2];
    cone.label = name + " cone";
    cone.unit = "deg";
    cone.value = RadToDeg(ik.joints.cone_rad[arm]);
    cone.lower = 0;
    cone.upper = RadToDeg(limits.spherical_cone_max_rad);
  }
  // The margins as CalcInverseKinematics judged them (one verdict, not a second one here).
  for (const robot::RsrLimitCheck& check : ik.checks) {
    const int slot = check.joint == robot::RsrJointKind::kRotary ? 0 : check.joint == robot::RsrJointKind::kStroke ? 1 : 2;
    const double scale = check.joint == robot::RsrJointKind::kStroke ? kMToMm : kRadToDeg;
    view.gauges[3 * check.arm + slot].margin = check.margin * scale;
  }
  return view;
}

}  // namespace robossis::panel
