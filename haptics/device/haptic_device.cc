#include "haptics/device/haptic_device.h"

#include <algorithm>
#include <cmath>

namespace robossis::haptics {

const char* ToString(DeviceStatus status) {
  switch (status) {
    case DeviceStatus::kOk: return "ok";
    case DeviceStatus::kNotOpen: return "not_open";
    case DeviceStatus::kStale: return "stale";
    case DeviceStatus::kInvalidReading: return "invalid_reading";
    case DeviceStatus::kTimeout: return "timeout";
    case DeviceStatus::kCommError: return "comm_error";
    case DeviceStatus::kDeviceLost: return "device_lost";
    case DeviceStatus::kEndOfScript: return "end_of_script";
  }
  return "unknown";
}

namespace {

bool IsFinite(const DeviceState& s) {
  return s.X_OH.matrix().allFinite() && s.v_O.allFinite() && s.w_O.allFinite() && std::isfinite(s.gripper_angle_rad);
}

// Scales v to norm max if longer (keeps the direction). A non-finite v becomes zero.
bool Clamp(Eigen::Vector3d& v, double max) {
  if (!v.allFinite()) {
    v.setZero();
    return true;
  }
  const double n = v.norm();
  if (n <= max) return false;
  v *= max / n;
  return true;
}

}  // namespace

const DeviceState& HapticDevice::Read(double now_s) noexcept {
  DeviceState raw = have_good_ ? last_good_ : DeviceState{};
  raw.time_s = now_s;
  DeviceStatus status = ReadRaw(now_s, raw);
  if (status == DeviceStatus::kOk && !IsFinite(raw)) status = DeviceStatus::kInvalidReading;
  if (status == DeviceStatus::kOk && (!(now_s - raw.time_s <= limits_.stale_after_s) || raw.time_s > now_s ||
                                      (have_good_ && raw.time_s < last_good_.time_s))) {
    status = DeviceStatus::kStale;
  }
  if (status == DeviceStatus::kOk) {
    raw.status = status;
    last_good_ = raw;
    have_good_ = true;
    state_ = raw;
  } else {
    // Keep the last good pose (nothing downstream jumps), at rest, with the failure's status and no button held.
    state_ = have_good_ ? last_good_ : DeviceState{};
    state_.time_s = now_s;
    state_.status = status;
    state_.buttons = 0;
    state_.v_O.setZero();
    state_.w_O.setZero();
  }
  return state_;
}

DeviceWriteReport HapticDevice::Write(const DeviceCommand& command) noexcept {
  DeviceWriteReport report;
  DeviceCommand c = command;
  if (!forces_enabled_ || !state_.ok()) {
    c = DeviceCommand{};
    report.zeroed = true;
  } else {
    report.clamped = Clamp(c.f_O, limits_.max_force_n);
    report.clamped = Clamp(c.tau_O, limits_.max_torque_nm) || report.clamped;
    if (!std::isfinite(c.gripper_force_n)) {
      c.gripper_force_n = 0;
      report.clamped = true;
    } else if (std::abs(c.gripper_force_n) > limits_.max_gripper_force_n) {
      c.gripper_force_n = std::copysign(limits_.max_gripper_force_n, c.gripper_force_n);
      report.clamped = true;
    }
  }
  report.status = WriteRaw(c);
  return report;
}

DeviceStatus HapticDevice::EnableForces(bool enabled) noexcept {
  if (!enabled) WriteRaw(DeviceCommand{});
  const DeviceStatus status = SetForcesEnabledRaw(enabled);
  forces_enabled_ = enabled && status == DeviceStatus::kOk;
  return status;
}

}  // namespace robossis::haptics
