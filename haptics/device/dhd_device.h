#pragma once
// The Force Dimension sigma.7 through the vendor's SDK (libdhd, loaded at run time: dhd_library.h).
//
// A thin translation of HapticDevice's raw calls into SDK calls; the limits, the zeroing after a bad read and the
// enable state live in HapticDevice. Every SDK error (device lost, USB timeout, communication error) becomes a
// DeviceStatus, so that the runtime zeroes the force and faults. Read/Write/EnableForces are allocation-free
// (pointer calls into the SDK) and are called from the haptic loop's thread only.
//
// Optionally (DhdOptions::enable_hold) the SDK's robotic regulation (libdrd) holds the handle at a position, for
// homing or while the follower is disabled: HoldAt/HoldHere/ReleaseHold, called outside the haptic tick (the SDK
// starts and stops its own regulation thread). While held, Write sends nothing: the regulation owns the motors.

#include <memory>
#include <string>

#include <Eigen/Core>

#include "haptics/device/dhd_library.h"
#include "haptics/device/dhd_options.h"
#include "haptics/device/haptic_device.h"

namespace robossis::haptics {

// What the SDK says about the opened device and itself.
struct DhdDeviceInfo {
  int id = -1;           // the SDK's device id
  int system_type = 0;   // dhdGetSystemType (dhd::kDeviceSigma331 for a sigma.7)
  std::string system_name;
  int serial = -1;
  std::string sdk_version;  // "major.minor.release.revision"
  std::string library_path;  // libdhd, or libdrd when the hold is enabled
  bool hold_available = false;
};

class DhdDevice final : public HapticDevice {
 public:
  // Loads the SDK, opens the device the options choose (the first sigma.7, or by serial or index), sets the velocity
  // estimator window and leaves forces disabled. Throws std::runtime_error: the library not found (every path
  // tried), a function missing (its name), no device or not a sigma.7 (what was found), or an SDK error (its text).
  static std::unique_ptr<DhdDevice> Open(const DhdOptions& options);
  ~DhdDevice() override;  // releases a hold, stops the forces and closes the device

  const char* name() const noexcept override { return "dhd"; }
  const DhdDeviceInfo& info() const { return info_; }
  // One line for the log: "sigma.7 (type 104) serial 1234, SDK 3.17.1.0 from /usr/local/lib/libdhd.so".
  std::string Describe() const;

  // The hold (needs DhdOptions::enable_hold); not real-time. HoldAt moves the handle to p_O (m, device frame) and
  // holds it there, keeping its current orientation; HoldHere holds the current pose. ReleaseHold stops the
  // regulation with forces left on and zero force sent, in the enable state the runtime last chose. Each returns
  // kNotOpen without libdrd, or the SDK's error as a status.
  DeviceStatus HoldAt(const Eigen::Vector3d& p_O) noexcept;
  DeviceStatus HoldHere() noexcept;
  DeviceStatus ReleaseHold() noexcept;
  bool holding() const noexcept { return holding_; }

  // The SDK error code behind the last status that was not ok (dhd::kNoError if none), and its text.
  int last_sdk_error() const noexcept { return last_error_; }
  const char* last_sdk_error_text() const noexcept;

 protected:
  DeviceStatus ReadRaw(double now_s, DeviceState& state) noexcept override;
  DeviceStatus WriteRaw(const DeviceCommand& command) noexcept override;
  DeviceStatus SetForcesEnabledRaw(bool enabled) noexcept override;

 private:
  DhdDevice(const DeviceLimits& limits, std::shared_ptr<SharedLibrary> library, const DhdApi& api);
  void OpenDevice(const DhdOptions& options);  // throws
  // The status for a call that returned `result` (< 0: an error, read from dhdErrorGetLast).
  DeviceStatus Check(int result) noexcept;

  // Starts the regulation (position and rotation); on failure stops it again.
  DeviceStatus StartRegulation() noexcept;

  std::shared_ptr<SharedLibrary> library_;
  DhdApi api_;
  DrdApi drd_{};
  bool drd_open_ = false;
  bool holding_ = false;
  char id_ = -1;
  bool open_ = false;
  int last_error_ = dhd::kNoError;
  DhdDeviceInfo info_;
};

// The SDK error code as a device status: timeout → kTimeout, no device / not available / not ready → kDeviceLost,
// anything else (communication error, busy, unknown) → kCommError.
DeviceStatus DeviceStatusFromDhdError(int error) noexcept;

// The factory's entry points for `--device dhd[:...]`.
std::unique_ptr<HapticDevice> OpenDhdDevice(const DhdOptions& options);
// "dhd" or "dhd:...".
bool IsDhdDeviceSpec(const std::string& spec);
// The options of <data dir>/config/dhd.yaml, then the spec's keys (dhd_options.h), with the runtime's `limits`.
// Throws std::invalid_argument for a bad spec, std::runtime_error as DhdDevice::Open.
std::unique_ptr<HapticDevice> OpenDhdDevice(const std::string& spec, const DeviceLimits& limits);

}  // namespace robossis::haptics
