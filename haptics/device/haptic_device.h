#pragma once
// The one interface to a haptic device (the leader's sigma.7): a timestamped state in, a wrench out. Every back end
// (simulated sigma.7 + hand, replay of a recorded hand, the Force Dimension SDK) derives from HapticDevice and
// implements only the raw calls; the checks every device needs live here, once:
//   - the device's own limits: the commanded force, torque and gripper force are clamped (keeping the direction)
//     to DeviceLimits before they reach the back end;
//   - a failed, non-finite or stale read zeroes the force: Write() sends zero until a good read comes back;
//   - forces are sent only while enabled.
// The shape follows what the Force Dimension SDK offers (dhdGetPositionAndOrientationFrame, dhdGetLinearVelocity,
// dhdGetAngularVelocityRad, dhdGetButtonMask, dhdGetGripperAngleRad, dhdSetForceAndTorqueAndGripperForce,
// dhdEnableForce), so its back end is a thin translation.
//
// Frames: O is the device base, H the handle. SI units. Read(), Write() and EnableForces() are called from the
// haptic loop's thread only: noexcept, allocation-free, lock-free (back ends keep that promise).

#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace robossis::haptics {

enum class DeviceStatus : std::uint8_t {
  kOk,
  kNotOpen,         // the back end has no device (not opened, or closed)
  kStale,           // the reading is older than DeviceLimits::stale_after_s, from the future, or older than the last
  kInvalidReading,  // a non-finite value in the reading
  kTimeout,         // the device did not answer in time (USB timeout)
  kCommError,       // a communication error reported by the device
  kDeviceLost,      // unplugged, or the device reported itself gone
  kEndOfScript,     // replay: the recorded trajectory is over (the hand is at rest at its last sample)
};
const char* ToString(DeviceStatus status);

// Button bits of DeviceState::buttons. Bit 0 is the sigma.7's user button, the operator-presence switch.
inline constexpr std::uint32_t kPresenceButton = 1u << 0;

struct DeviceState {
  double time_s = 0;  // when the reading was taken (runtime clock); ReadRaw starts it at now_s, a buffered back end
                      // sets its sample's own time
  Eigen::Isometry3d X_OH = Eigen::Isometry3d::Identity();  // handle pose
  Eigen::Vector3d v_O = Eigen::Vector3d::Zero();           // handle linear velocity (m/s)
  Eigen::Vector3d w_O = Eigen::Vector3d::Zero();           // handle angular velocity (rad/s)
  std::uint32_t buttons = 0;                               // bit mask, kPresenceButton = bit 0
  double gripper_angle_rad = 0;
  DeviceStatus status = DeviceStatus::kNotOpen;
  bool ok() const noexcept { return status == DeviceStatus::kOk; }
  bool presence() const noexcept { return ok() && (buttons & kPresenceButton) != 0; }
};

struct DeviceCommand {
  Eigen::Vector3d f_O = Eigen::Vector3d::Zero();    // force on the hand (N)
  Eigen::Vector3d tau_O = Eigen::Vector3d::Zero();  // torque on the hand (N·m)
  double gripper_force_n = 0;
};

// The device's own limits (sigma.7: 20 N, 0.4 N·m peak; the gripper's 8 N is the sigma.7 data sheet's figure,
// [assumed] here since the paper does not give it). stale_after_s: [assumed] a reading older than 5 ticks at
// 1 kHz is too old to render a wall on.
struct DeviceLimits {
  double max_force_n = 20.0;
  double max_torque_nm = 0.4;
  double max_gripper_force_n = 8.0;
  double stale_after_s = 0.005;
};

// What Write() did with the last command.
struct DeviceWriteReport {
  DeviceStatus status = DeviceStatus::kNotOpen;  // the back end's answer
  bool clamped = false;                          // the command exceeded a limit and was scaled down
  bool zeroed = false;                           // zero was sent: forces disabled or the last read was not ok
};

class HapticDevice {
 public:
  explicit HapticDevice(const DeviceLimits& limits) : limits_(limits) {}
  virtual ~HapticDevice() = default;
  HapticDevice(const HapticDevice&) = delete;
  HapticDevice& operator=(const HapticDevice&) = delete;

  // Reads the device at runtime time now_s. The result's status is not ok if the back end failed, a value is not
  // finite, or the reading is stale; such a state keeps the last good pose so that nothing downstream jumps.
  const DeviceState& Read(double now_s) noexcept;
  // Clamps to the limits and sends; sends zero while forces are disabled or after a read that was not ok.
  DeviceWriteReport Write(const DeviceCommand& command) noexcept;
  // Enables or disables the device's force output (disabling also sends zero). Returns the back end's status.
  DeviceStatus EnableForces(bool enabled) noexcept;

  const DeviceState& state() const noexcept { return state_; }
  bool forces_enabled() const noexcept { return forces_enabled_; }
  const DeviceLimits& limits() const noexcept { return limits_; }
  virtual const char* name() const noexcept = 0;

 protected:
  // Back end: fill `state` (time_s is preset to now_s; status is set by the base from the return value and checks).
  virtual DeviceStatus ReadRaw(double now_s, DeviceState& state) noexcept = 0;
  // Back end: send an already clamped command.
  virtual DeviceStatus WriteRaw(const DeviceCommand& command) noexcept = 0;
  virtual DeviceStatus SetForcesEnabledRaw(bool enabled) noexcept = 0;

 private:
  DeviceLimits limits_;
  DeviceState state_;
  DeviceState last_good_;
  bool have_good_ = false;
  bool forces_enabled_ = false;
};

}  // namespace robossis::haptics
