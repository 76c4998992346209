#include "haptics/device/dhd_device.h"

#include <stdexcept>

#include "src/core/config.h"

namespace robossis::haptics {

namespace {

bool IsSigma7(int system_type) {
  return system_type == dhd::kDeviceSigma331 || system_type == dhd::kDeviceSigma331Left;
}

std::string ErrorText(const DhdApi& api) {
  const int error = api.dhdErrorGetLast();
  const char* text = api.dhdErrorGetStr(error);
  return std::string(text != nullptr ? text : "unknown error") + " (SDK error " + std::to_string(error) + ")";
}

std::string SystemName(const DhdApi& api, char id) {
  const char* name = api.dhdGetSystemName(id);
  return name != nullptr ? name : "unnamed device";
}

}  // namespace

DeviceStatus DeviceStatusFromDhdError(int error) noexcept {
  switch (error) {
    case dhd::kErrorTimeout: return DeviceStatus::kTimeout;
    case dhd::kErrorNoDeviceFound:
    case dhd::kErrorNotAvailable:
    case dhd::kErrorDeviceNotReady: return DeviceStatus::kDeviceLost;
    default: return DeviceStatus::kCommError;
  }
}

DhdDevice::DhdDevice(const DeviceLimits& limits, std::shared_ptr<SharedLibrary> library, const DhdApi& api)
    : HapticDevice(limits), library_(std::move(library)), api_(api) {
  info_.library_path = library_->path();
}

std::unique_ptr<DhdDevice> DhdDevice::Open(const DhdOptions& options) {
  std::shared_ptr<SharedLibrary> library =
      options.enable_hold
          ? SharedLibrary::OpenFirst("the Force Dimension SDK with its robotic regulation (libdrd, for the hold)",
                                     DrdLibraryCandidates(options.drd_library_path))
          : SharedLibrary::OpenFirst("the Force Dimension SDK (libdhd)", DhdLibraryCandidates(options.library_path));
  const DhdApi api = LoadDhdApi(*library);
  std::unique_ptr<DhdDevice> device(new DhdDevice(options.limits, library, api));
  if (options.enable_hold) device->drd_ = LoadDrdApi(*library);
  device->OpenDevice(options);
  return device;
}

void DhdDevice::OpenDevice(const DhdOptions& options) {
  const std::string where = info_.library_path + ": ";
  const int count = api_.dhdGetDeviceCount();
  if (count < 0) throw std::runtime_error(where + "dhdGetDeviceCount failed: " + ErrorText(api_));
  if (count == 0) throw std::runtime_error(where + "no Force Dimension device is connected");
  int id = -1;
  if (options.serial >= 0) {
    id = api_.dhdOpenSerial(options.serial);
    if (id < 0) {
      throw std::runtime_error(where + "cannot open the device with serial " + std::to_string(options.serial) +
                               ": " + ErrorText(api_));
    }
  } else if (options.index >= 0) {
    if (options.index >= count) {
      throw std::runtime_error(where + "device index " + std::to_string(options.index) + " asked for, but " +
                               std::to_string(count) + " device(s) are connected");
    }
    id = api_.dhdOpenID(static_cast<char>(options.index));
    if (id < 0) {
      throw std::runtime_error(where + "cannot open device index " + std::to_string(options.index) + ": " +
                               ErrorText(api_));
    }
  } else {
    std::string found;  // what the search saw, for the error
    for (int i = 0; i < count && id < 0; ++i) {
      const int candidate = api_.dhdOpenID(static_cast<char>(i));
      if (candidate < 0) {
        found += "; index " + std::to_string(i) + ": cannot open (" + ErrorText(api_) + ")";
        continue;
      }
      const int type = api_.dhdGetSystemType(static_cast<char>(candidate));
      if (IsSigma7(type)) {
        id = candidate;
      } else {
        found += "; index " + std::to_string(i) + ": " + SystemName(api_, static_cast<char>(candidate)) +
                 " (type " + std::to_string(type) + ")";
        api_.dhdClose(static_cast<char>(candidate));
      }
    }
    if (id < 0) {
      throw std::runtime_error(where + "no sigma.7 among " + std::to_string(count) + " device(s)" + found);
    }
  }
  id_ = static_cast<char>(id);
  open_ = true;  // from here on the destructor closes it
  info_.id = id;
  info_.system_type = api_.dhdGetSystemType(id_);
  info_.system_name = SystemName(api_, id_);
  if (!IsSigma7(info_.system_type)) {
    throw std::runtime_error(where + "the device chosen is a " + info_.system_name + " (type " +
                             std::to_string(info_.system_type) + "), not a sigma.7 (type " +
                             std::to_string(dhd::kDeviceSigma331) + " or " +
                             std::to_string(dhd::kDeviceSigma331Left) + ")");
  }
  unsigned short serial = 0;
  if (api_.dhdGetSerialNumber(&serial, id_) >= 0) info_.serial = serial;
  int major = 0, minor = 0, release = 0, revision = 0;
  api_.dhdGetSDKVersion(&major, &minor, &release, &revision);
  info_.sdk_version = std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(release) + "." +
                      std::to_string(revision);
  // The velocity estimator window (dhd.yaml: the SDK's 20 ms default lags enough to make a wrist damper active).
  if (api_.dhdConfigLinearVelocity(options.velocity_window_ms, dhd::kVelocityWindowing, id_) < 0 ||
      api_.dhdConfigAngularVelocity(options.velocity_window_ms, dhd::kVelocityWindowing, id_) < 0) {
    throw std::runtime_error(where + "cannot set the velocity window to " +
                             std::to_string(options.velocity_window_ms) + " ms: " + ErrorText(api_));
  }
  // Forces start disabled: the runtime enables them when its state machine says so.
  if (api_.dhdEnableForce(0, id_) < 0) throw std::runtime_error(where + "dhdEnableForce failed: " + ErrorText(api_));
  if (options.enable_hold) {
    if (drd_.drdOpenID(id_) < 0) throw std::runtime_error(where + "drdOpenID failed: " + ErrorText(api_));
    drd_open_ = true;
    info_.hold_available = true;
  }
}

DhdDevice::~DhdDevice() {
  if (holding_) drd_.drdStop(false, id_);
  if (drd_open_) drd_.drdClose(id_);
  if (open_) {
    api_.dhdSetForceAndTorqueAndGripperForce(0, 0, 0, 0, 0, 0, 0, id_);
    api_.dhdEnableForce(0, id_);
    api_.dhdStop(id_);
    api_.dhdClose(id_);
  }
}

std::string DhdDevice::Describe() const {
  return info_.system_name + " (type " + std::to_string(info_.system_type) + ") serial " +
         std::to_string(info_.serial) + ", SDK " + info_.sdk_version + " from " + info_.library_path;
}

const char* DhdDevice::last_sdk_error_text() const noexcept {
  const char* text = api_.dhdErrorGetStr(last_error_);
  return text != nullptr ? text : "unknown error";
}

DeviceStatus DhdDevice::Check(int result) noexcept {
  if (result >= 0) return DeviceStatus::kOk;  // positive values (time guard, motor saturated) are not errors
  last_error_ = api_.dhdErrorGetLast();
  return DeviceStatusFromDhdError(last_error_);
}

DeviceStatus DhdDevice::ReadRaw(double /*now_s*/, DeviceState& state) noexcept {
  if (!open_) return DeviceStatus::kNotOpen;
  double p[3], R[3][3], v[3], w[3], gripper = 0;
  DeviceStatus status = Check(api_.dhdGetPositionAndOrientationFrame(&p[0], &p[1], &p[2], R, id_));
  if (status == DeviceStatus::kOk) status = Check(api_.dhdGetLinearVelocity(&v[0], &v[1], &v[2], id_));
  if (status == DeviceStatus::kOk) status = Check(api_.dhdGetAngularVelocityRad(&w[0], &w[1], &w[2], id_));
  if (status == DeviceStatus::kOk) status = Check(api_.dhdGetGripperAngleRad(&gripper, id_));
  if (status != DeviceStatus::kOk) return status;
  state.X_OH.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
  // The SDK's frame is row-major: R[i][j] is row i, column j of the handle's rotation in the base frame.
  Eigen::Matrix3d rotation;
  rotation << R[0][0], R[0][1], R[0][2], R[1][0], R[1][1], R[1][2], R[2][0], R[2][1], R[2][2];
  state.X_OH.linear() = rotation;
  state.v_O = Eigen::Vector3d(v[0], v[1], v[2]);
  state.w_O = Eigen::Vector3d(w[0], w[1], w[2]);
  state.gripper_angle_rad = gripper;
  state.buttons = api_.dhdGetButtonMask(id_);
  return DeviceStatus::kOk;
}

DeviceStatus DhdDevice::WriteRaw(const DeviceCommand& c) noexcept {
  if (!open_) return DeviceStatus::kNotOpen;
  if (holding_) return DeviceStatus::kOk;  // the SDK's regulation owns the motors
  return Check(api_.dhdSetForceAndTorqueAndGripperForce(c.f_O.x(), c.f_O.y(), c.f_O.z(), c.tau_O.x(), c.tau_O.y(),
                                                        c.tau_O.z(), c.gripper_force_n, id_));
}

DeviceStatus DhdDevice::SetForcesEnabledRaw(bool enabled) noexcept {
  if (!open_) return DeviceStatus::kNotOpen;
  if (holding_) return DeviceStatus::kOk;  // the regulation keeps the forces on; ReleaseHold restores the choice
  return Check(api_.dhdEnableForce(enabled ? 1 : 0, id_));
}

DeviceStatus DhdDevice::StartRegulation() noexcept {
  if (!open_ || !drd_open_) return DeviceStatus::kNotOpen;
  DeviceStatus status = Check(drd_.drdRegulatePos(true, id_));
  if (status == DeviceStatus::kOk) status = Check(drd_.drdRegulateRot(true, id_));
  if (status == DeviceStatus::kOk) status = Check(drd_.drdStart(id_));
  return status;
}

DeviceStatus DhdDevice::HoldAt(const Eigen::Vector3d& p_O) noexcept {
  if (!p_O.allFinite()) return DeviceStatus::kInvalidReading;
  DeviceStatus status = holding_ ? DeviceStatus::kOk : StartRegulation();  // a new target for a running hold
  if (status != DeviceStatus::kOk) return status;
  double p[dhd::kMaxDof] = {}, R[3][3];
  // The current pose in the regulation's own coordinates, so that only the position changes.
  status = Check(drd_.drdGetPositionAndOrientation(p, R, id_));
  if (status == DeviceStatus::kOk) {
    p[0] = p_O.x();
    p[1] = p_O.y();
    p[2] = p_O.z();
    status = Check(drd_.drdMoveTo(p, /*block=*/false, id_));
  }
  if (status != DeviceStatus::kOk) {
    drd_.drdStop(false, id_);
    holding_ = false;
    return status;
  }
  holding_ = true;
  return DeviceStatus::kOk;
}

DeviceStatus DhdDevice::HoldHere() noexcept {
  DeviceStatus status = holding_ ? DeviceStatus::kOk : StartRegulation();
  if (status == DeviceStatus::kOk) status = Check(drd_.drdHold(id_));
  if (status != DeviceStatus::kOk) {
    if (drd_open_) drd_.drdStop(false, id_);
    holding_ = false;
    return status;
  }
  holding_ = true;
  return DeviceStatus::kOk;
}

DeviceStatus DhdDevice::ReleaseHold() noexcept {
  if (!holding_) return DeviceStatus::kOk;
  holding_ = false;
  // Forces stay on through the stop (no jolt into the brakes); then zero force, and the enable state of the runtime.
  DeviceStatus status = Check(drd_.drdStop(true, id_));
  const DeviceStatus zero = WriteRaw(DeviceCommand{});
  const DeviceStatus enable = SetForcesEnabledRaw(forces_enabled());
  if (status == DeviceStatus::kOk) status = zero;
  if (status == DeviceStatus::kOk) status = enable;
  return status;
}

std::unique_ptr<HapticDevice> OpenDhdDevice(const DhdOptions& options) { return DhdDevice::Open(options); }

bool IsDhdDeviceSpec(const std::string& spec) { return spec == "dhd" || spec.rfind("dhd:", 0) == 0; }

std::unique_ptr<HapticDevice> OpenDhdDevice(const std::string& spec, const DeviceLimits& limits) {
  DhdOptions options = ParseDhdOptions(spec, DhdOptionsFromYaml(DefaultDataDir() / "config" / "dhd.yaml"));
  options.limits = limits;
  return DhdDevice::Open(options);
}

}  // namespace robossis::haptics
