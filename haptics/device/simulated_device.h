#pragma once
// The simulated and replay back ends of HapticDevice: the simulated sigma.7 (SimulatedSigma7) held by the hand
// model, the hand pulled toward a scripted target. The physics advances to each read's time with the wrench last
// written held constant, so the device runs alike in wall-clock time (a live loop reading a MonotonicClock) and in
// simulated time (a test stepping a SimulatedClock): the device has no clock of its own.
//
// The hand holds the presence button while its script runs, so a scripted or recorded hand moves the robot
// without a person. A replay script reports kEndOfScript once it is over (the hand rests at its last sample).
//
// Failure injection (tests, and the demo's fault drill): the next N reads fail, return a non-finite pose, or
// return a stale sample. Injection may be requested from any thread (atomics); it is consumed by the loop's reads.

#include <atomic>
#include <functional>
#include <limits>
#include <string>

#include "haptics/device/device_sim.h"
#include "haptics/device/haptic_device.h"
#include "robot/sigma7_model.h"

namespace robossis::haptics {

// The hand's target over time (t from the script's start, s), in the device base O.
struct HandScript {
  std::string name;
  double duration_s = std::numeric_limits<double>::infinity();
  std::function<HandTarget(double t)> target;  // must not allocate (called from the haptic loop)
  bool end_of_script_status = false;           // report kEndOfScript after duration_s (replay)
};

enum class InjectedFault : std::uint8_t {
  kNone,
  kFailedRead,  // the back end answers kTimeout
  kNonFinite,   // the reading carries a NaN position
  kStale,       // the reading is a sample 1 s old
};

class SimulatedDevice final : public HapticDevice {
 public:
  SimulatedDevice(const robot::Sigma7Model& model, const DeviceSimParams& device, const HandParams& hand,
                  HandScript script, const DeviceLimits& limits);

  const char* name() const noexcept override { return name_.c_str(); }
  // Makes the next `reads` reads fail in the given way. Any thread.
  void Inject(InjectedFault fault, int reads) noexcept;

  const HandScript& script() const { return script_; }
  // The script time of the last read (s since the first read); the handle's true pose (before any injection).
  double script_time_s() const noexcept { return t_phys_ - t_start_; }
  const SimulatedSigma7& sim() const { return sim_; }
  const Eigen::Vector3d& last_force_O() const { return command_.f_O; }

 protected:
  DeviceStatus ReadRaw(double now_s, DeviceState& state) noexcept override;
  DeviceStatus WriteRaw(const DeviceCommand& command) noexcept override;
  DeviceStatus SetForcesEnabledRaw(bool enabled) noexcept override;

 private:
  HandTarget TargetAt(double t) const noexcept;

  SimulatedSigma7 sim_;
  HandScript script_;
  std::string name_;
  DeviceCommand command_;
  bool started_ = false;
  double t_start_ = 0;
  double t_phys_ = 0;
  std::atomic<InjectedFault> fault_{InjectedFault::kNone};
  std::atomic<int> fault_reads_{0};
};

}  // namespace robossis::haptics
