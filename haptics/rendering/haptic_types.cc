#include "haptics/rendering/haptic_types.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace robossis::haptics {

const char* ToString(HapticStatus status) {
  switch (status) {
    case HapticStatus::kFree: return "free";
    case HapticStatus::kContact: return "contact";
    case HapticStatus::kDeepPenetration: return "deep_penetration";
    case HapticStatus::kFault: return "fault";
  }
  return "unknown";
}

Eigen::Isometry3d HcToRsrMap::ToRsr(const Eigen::Isometry3d& X_OH) const noexcept {
  Eigen::Isometry3d X_FM = Eigen::Isometry3d::Identity();
  X_FM.translation() = X_FM_anchor.translation() + frame.LinearToRsr(X_OH.translation() - X_OH_anchor.translation());
  X_FM.linear() = frame.RotationToRsr(X_OH.linear() * X_OH_anchor.linear().transpose()) * X_FM_anchor.linear();
  return X_FM;
}

Eigen::Isometry3d HcToRsrMap::ToHc(const Eigen::Isometry3d& X_FM) const noexcept {
  Eigen::Isometry3d X_OH = Eigen::Isometry3d::Identity();
  X_OH.translation() = X_OH_anchor.translation() + frame.LinearToHc(X_FM.translation() - X_FM_anchor.translation());
  X_OH.linear() = frame.RotationToHc(X_FM.linear() * X_FM_anchor.linear().transpose()) * X_OH_anchor.linear();
  return X_OH;
}

bool SaturateNorm(Eigen::Vector3d& v, double max_norm) noexcept {
  const double n = v.norm();
  if (n > max_norm) {
    v *= max_norm / n;
    return true;
  }
  return false;
}

HapticRenderer::HapticRenderer(const robot::RsrModel& model, const HcToRsrMap& map, const WrenchLimits& limits,
                               double rate_hz)
    : model_(model), map_(map), limits_(limits), dt_(1.0 / rate_hz) {
  if (!(rate_hz > 0) || !(limits.max_force_n > 0) || !(limits.max_torque_nm > 0)) {
    throw std::invalid_argument("haptic renderer: rate_hz and wrench caps must be positive (rate " +
                                std::to_string(rate_hz) + " Hz)");
  }
  try {
    map.frame.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("haptic renderer: HC -> RSR frame map: ") + e.what());
  }
}

void HapticRenderer::Reset(const Eigen::Isometry3d& X_OH) noexcept {
  energy_force_j_ = 0;
  energy_torque_j_ = 0;
  ResetMethod(X_OH);
}

namespace {
// One port of the passivity controller: updates the observed energy with the force about to be displayed and,
// on a deficit, adds the damper that removes it. Returns true if the controller acted.
bool PassivityPort(Eigen::Vector3d& f, const Eigen::Vector3d& v, double dt, double max_damping, double max_norm,
                   double& energy) noexcept {
  energy -= f.dot(v) * dt;
  const double v2 = v.squaredNorm();
  if (energy >= 0 || v2 < 1e-18) return false;
  const double alpha = std::min(max_damping, -energy / (dt * v2));
  const Eigen::Vector3d f_before = f;
  f -= alpha * v;
  SaturateNorm(f, max_norm);
  energy += (f_before - f).dot(v) * dt;  // the energy the added damper actually dissipates
  return true;
}
}  // namespace

HapticStatus HapticRenderer::Tick(const HapticInput& input, HapticOutput& output) noexcept {
  output.f_O.setZero();
  output.tau_O.setZero();
  output.saturated = false;
  if (!input.X_OH.matrix().allFinite() || !input.v_O.allFinite() || !input.w_O.allFinite()) {
    output.status = HapticStatus::kFault;
    return output.status;
  }
  return RenderState(map_.ToRsr(input.X_OH), input, output);
}

HapticStatus HapticRenderer::TickRsr(const Eigen::Isometry3d& X_FM, const HapticInput& input,
                                     HapticOutput& output) noexcept {
  output.f_O.setZero();
  output.tau_O.setZero();
  output.saturated = false;
  if (!X_FM.matrix().allFinite() || !input.v_O.allFinite() || !input.w_O.allFinite()) {
    output.status = HapticStatus::kFault;
    return output.status;
  }
  return RenderState(X_FM, input, output);
}

HapticStatus HapticRenderer::RenderState(const Eigen::Isometry3d& X_FM, const HapticInput& input,
                                         HapticOutput& output) noexcept {
  // The hand's state in RSR space: the pose given, the velocities through the same frame map as the pose.
  RsrSideState state;
  state.X_FM = X_FM;
  state.v_F = map_.frame.LinearToRsr(input.v_O);
  state.w_F = map_.frame.AngularToRsr(input.w_O);
  Eigen::Vector3d f_F, tau_F;
  HapticStatus status = Render(state, f_F, tau_F);
  if (!f_F.allFinite() || !tau_F.allFinite()) {
    output.status = HapticStatus::kFault;
    return output.status;
  }
  // The wall is felt at the HC unscaled: the force on the hand is the wall force in RSR space, rotated into O.
  // The caps are on norms, which the rotation keeps.
  output.saturated = SaturateNorm(f_F, limits_.max_force_n);
  output.saturated = SaturateNorm(tau_F, limits_.max_torque_nm) || output.saturated;
  Eigen::Vector3d f_O = map_.frame.WrenchToHc(f_F);
  Eigen::Vector3d tau_O = map_.frame.WrenchToHc(tau_F);
  // The passivity ports work in O: the power into the hand is the displayed force times the hand's own velocity.
  if (passivity_.enabled) {
    if (status == HapticStatus::kFree) {
      energy_force_j_ = 0;
      energy_torque_j_ = 0;
    } else {
      PassivityPort(f_O, input.v_O, dt_, passivity_.max_damping_ns_per_m, limits_.max_force_n, energy_force_j_);
      PassivityPort(tau_O, input.w_O, dt_, passivity_.max_damping_nms_per_rad, limits_.max_torque_nm,
                    energy_torque_j_);
    }
  }
  output.f_O = f_O;
  output.tau_O = tau_O;
  output.status = status;
  return status;
}

}  // namespace robossis::haptics
