// The checks every haptic device back end inherits from HapticDevice: limits clamp the wrench keeping its
// direction, a failed, non-finite or stale read zeroes the force, and nothing is sent while forces are disabled.

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "haptics/device/haptic_device.h"
#include "tests/support/alloc_counter.h"

namespace robossis::haptics {
namespace {

// A scripted back end: returns what the test sets, records what it was sent.
class ScriptedDevice final : public HapticDevice {
 public:
  ScriptedDevice() : HapticDevice(DeviceLimits{}) {}
  const char* name() const noexcept override { return "scripted"; }
  DeviceStatus next_status = DeviceStatus::kOk;
  DeviceState next;
  double age_s = 0;
  DeviceCommand sent;
  bool enabled = false;

 protected:
  DeviceStatus ReadRaw(double now_s, DeviceState& state) noexcept override {
    const double t = now_s - age_s;
    state = next;
    state.time_s = t;
    return next_status;
  }
  DeviceStatus WriteRaw(const DeviceCommand& command) noexcept override {
    sent = command;
    return DeviceStatus::kOk;
  }
  DeviceStatus SetForcesEnabledRaw(bool on) noexcept override {
    enabled = on;
    return DeviceStatus::kOk;
  }
};

DeviceCommand Push(double fx, double tz) {
  DeviceCommand c;
  c.f_O = {fx, 0, 0};
  c.tau_O = {0, 0, tz};
  return c;
}

TEST(HapticDeviceTest, ClampsToTheDeviceLimitsKeepingTheDirection) {
  ScriptedDevice dev;
  dev.next.buttons = kPresenceButton;
  ASSERT_EQ(dev.EnableForces(true), DeviceStatus::kOk);
  ASSERT_TRUE(dev.Read(0.001).ok());
  DeviceCommand c;
  c.f_O = {30, 40, 0};   // 50 N
  c.tau_O = {0, 0, -1};  // 1 N·m
  c.gripper_force_n = 12;
  const DeviceWriteReport r = dev.Write(c);
  EXPECT_TRUE(r.clamped);
  EXPECT_FALSE(r.zeroed);
  EXPECT_NEAR(dev.sent.f_O.norm(), 20.0, 1e-12);
  EXPECT_NEAR(dev.sent.f_O.x() / dev.sent.f_O.y(), 0.75, 1e-12);
  EXPECT_NEAR(dev.sent.tau_O.z(), -0.4, 1e-12);
  EXPECT_DOUBLE_EQ(dev.sent.gripper_force_n, 8.0);
  EXPECT_TRUE(dev.state().presence());
}

TEST(HapticDeviceTest, AFailedNonFiniteOrStaleReadZeroesTheForceAndKeepsThePose) {
  ScriptedDevice dev;
  dev.EnableForces(true);
  dev.next.X_OH.translation() = Eigen::Vector3d(0.01, 0.02, 0.03);
  dev.next.buttons = kPresenceButton;
  ASSERT_TRUE(dev.Read(0.001).ok());
  dev.Write(Push(5, 0.1));
  EXPECT_DOUBLE_EQ(dev.sent.f_O.x(), 5.0);

  // Failed read (USB timeout).
  dev.next_status = DeviceStatus::kTimeout;
  dev.next.X_OH.translation() = Eigen::Vector3d(1, 1, 1);
  EXPECT_EQ(dev.Read(0.002).status, DeviceStatus::kTimeout);
  EXPECT_TRUE(dev.Write(Push(5, 0.1)).zeroed);
  EXPECT_EQ(dev.sent.f_O, Eigen::Vector3d::Zero());
  EXPECT_EQ(dev.state().X_OH.translation(), Eigen::Vector3d(0.01, 0.02, 0.03));  // last good pose
  EXPECT_FALSE(dev.state().presence());

  // Non-finite reading.
  dev.next_status = DeviceStatus::kOk;
  dev.next.X_OH.translation().x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(dev.Read(0.003).status, DeviceStatus::kInvalidReading);
  EXPECT_TRUE(dev.Write(Push(5, 0.1)).zeroed);

  // Stale: a buffered reading older than the limit.
  dev.next.X_OH.translation() = Eigen::Vector3d(0.01, 0.02, 0.04);
  dev.age_s = 0.02;
  EXPECT_EQ(dev.Read(0.004).status, DeviceStatus::kStale);
  EXPECT_TRUE(dev.Write(Push(5, 0.1)).zeroed);

  // A good read restores the force.
  dev.age_s = 0;
  ASSERT_TRUE(dev.Read(0.005).ok());
  EXPECT_FALSE(dev.Write(Push(5, 0.1)).zeroed);
  EXPECT_DOUBLE_EQ(dev.sent.f_O.x(), 5.0);
}

TEST(HapticDeviceTest, NothingIsSentWhileForcesAreDisabledAndNonFiniteCommandsAreZeroed) {
  ScriptedDevice dev;
  ASSERT_TRUE(dev.Read(0.001).ok());
  EXPECT_TRUE(dev.Write(Push(5, 0)).zeroed);
  EXPECT_EQ(dev.sent.f_O, Eigen::Vector3d::Zero());
  dev.EnableForces(true);
  EXPECT_TRUE(dev.enabled);
  EXPECT_TRUE(dev.Write(Push(std::numeric_limits<double>::infinity(), 0)).clamped);
  EXPECT_EQ(dev.sent.f_O, Eigen::Vector3d::Zero());
  dev.Write(Push(5, 0));
  dev.EnableForces(false);
  EXPECT_FALSE(dev.enabled);
  EXPECT_EQ(dev.sent.f_O, Eigen::Vector3d::Zero());  // disabling sends zero first
}

TEST(HapticDeviceTest, ReadAndWriteDoNotAllocate) {
  ScriptedDevice dev;
  dev.EnableForces(true);
  testing::AllocationCounter counter;
  for (int i = 1; i <= 100; ++i) {
    dev.Read(i * 1e-3);
    dev.Write(Push(1, 0.01));
  }
  EXPECT_EQ(counter.count(), 0u);
}

}  // namespace
}  // namespace robossis::haptics
