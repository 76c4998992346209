#include "haptics/device/simulated_device.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace robossis::haptics {

namespace {
// The physics advances in steps of at most this length between two reads, so that a late read (a missed deadline,
// a first read long after construction) integrates the hand with the same step as an on-time one. [assumed] 1 ms:
// the haptic period at the default 1 kHz.
constexpr double kMaxStepS = 1e-3;
}  // namespace

SimulatedDevice::SimulatedDevice(const robot::Sigma7Model& model, const DeviceSimParams& device,
                                 const HandParams& hand, HandScript script, const DeviceLimits& limits)
    : HapticDevice(limits), sim_(model, device, hand), script_(std::move(script)) {
  if (!script_.target) throw std::invalid_argument("simulated device: the hand script has no target");
  if (!(script_.duration_s > 0)) throw std::invalid_argument("simulated device: the script duration must be positive");
  name_ = script_.end_of_script_status ? "replay" : "sim";
  if (!script_.name.empty()) name_ += ":" + script_.name;
  sim_.Reset(script_.target(0).X_OH);
}

void SimulatedDevice::Inject(InjectedFault fault, int reads) noexcept {
  fault_.store(fault, std::memory_order_relaxed);
  fault_reads_.store(reads, std::memory_order_release);
}

HandTarget SimulatedDevice::TargetAt(double t) const noexcept {
  return script_.target(std::min(std::max(t, 0.0), script_.duration_s));
}

DeviceStatus SimulatedDevice::ReadRaw(double now_s, DeviceState& state) noexcept {
  if (!started_) {
    started_ = true;
    t_start_ = now_s;
    t_phys_ = now_s;
  }
  // Advance the hand and the handle to the read time, the displayed wrench held since the last write.
  while (t_phys_ < now_s) {
    const double dt = std::min(kMaxStepS, now_s - t_phys_);
    const double t_next = t_phys_ + dt;
    sim_.Step(dt, command_.f_O, command_.tau_O, TargetAt(t_next - t_start_));
    t_phys_ = t_next;
  }
  state.time_s = now_s;
  state.X_OH = sim_.pose();
  state.v_O = sim_.velocity();
  state.w_O = sim_.angular_velocity();
  state.gripper_angle_rad = 0;
  const bool running = script_time_s() < script_.duration_s;
  state.buttons = running ? kPresenceButton : 0u;

  if (fault_reads_.load(std::memory_order_acquire) > 0) {
    fault_reads_.fetch_sub(1, std::memory_order_acq_rel);
    switch (fault_.load(std::memory_order_relaxed)) {
      case InjectedFault::kNone: break;
      case InjectedFault::kFailedRead: return DeviceStatus::kTimeout;
      case InjectedFault::kNonFinite: state.X_OH.translation().x() = std::nan(""); break;
      case InjectedFault::kStale: state.time_s = now_s - 1.0; break;
    }
  }
  if (!running && script_.end_of_script_status) return DeviceStatus::kEndOfScript;
  return DeviceStatus::kOk;
}

DeviceStatus SimulatedDevice::WriteRaw(const DeviceCommand& command) noexcept {
  command_ = command;
  return DeviceStatus::kOk;
}

DeviceStatus SimulatedDevice::SetForcesEnabledRaw(bool enabled) noexcept {
  if (!enabled) command_ = DeviceCommand{};
  return DeviceStatus::kOk;
}

}  // namespace robossis::haptics
