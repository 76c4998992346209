// The Force Dimension SDK back end against the fake SDK (fake_dhd/): opening and choosing the device, the closed
// loop through the walls, the limits, every SDK failure as a device status with zero force, a library lacking a
// function, no library at all, and the DRD hold.

#include <dlfcn.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "haptics/device/dhd_device.h"
#include "haptics/rendering/renderer_factory.h"
#include "haptics/scenarios/scenario.h"
#include "robot/sigma7_model.h"
#include "src/core/config.h"
#include "test_util.h"
#include "tests/haptics/fake_dhd/fake_dhd_control.h"
#include "tests/support/alloc_counter.h"

namespace robossis::haptics {
namespace {

constexpr double kTick = 0.25e-3;  // 4 kHz

// The fake's test controls, looked up in the same library instance the back end opens.
class FakeSdk {
 public:
  explicit FakeSdk(const char* path) : handle_(dlopen(path, RTLD_NOW | RTLD_LOCAL)) {
    if (handle_ == nullptr) throw std::runtime_error(std::string("cannot load the fake SDK: ") + dlerror());
    Bind("fake_dhd_reset", reset);
    Bind("fake_dhd_set_devices", set_devices);
    Bind("fake_dhd_set_hand_target", set_hand_target);
    Bind("fake_dhd_set_hand_stiffness", set_hand_stiffness);
    Bind("fake_dhd_set_tick", set_tick);
    Bind("fake_dhd_unplug", unplug);
    Bind("fake_dhd_fail_next", fail_next);
    Bind("fake_dhd_nan_next", nan_next);
    Bind("fake_dhd_get_state", get_state);
    reset();
    set_tick(kTick);
  }
  ~FakeSdk() { dlclose(handle_); }
  FakeDhdState State() const {
    FakeDhdState s{};
    get_state(&s);
    return s;
  }
  Eigen::Vector3d Position() const {
    const FakeDhdState s = State();
    return {s.p[0], s.p[1], s.p[2]};
  }
  Eigen::Vector3d Force() const {
    const FakeDhdState s = State();
    return {s.f[0], s.f[1], s.f[2]};
  }

  void (*reset)();
  void (*set_devices)(int, const int*, const int*);
  void (*set_hand_target)(double, double, double);
  void (*set_hand_stiffness)(double);
  void (*set_tick)(double);
  void (*unplug)();
  void (*fail_next)(int, int);
  void (*nan_next)(int);
  void (*get_state)(FakeDhdState*);

 private:
  template <typename Fn>
  void Bind(const char* name, Fn& fn) {
    fn = reinterpret_cast<Fn>(dlsym(handle_, name));
    if (fn == nullptr) throw std::runtime_error(std::string("fake SDK lacks ") + name);
  }
  void* handle_;
};

DhdOptions FakeOptions() {
  DhdOptions o;
  o.library_path = FAKE_DHD_LIBRARY;
  return o;
}

std::string OpenError(const DhdOptions& options) {
  try {
    DhdDevice::Open(options);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

Eigen::Vector3d Centre() { return robot::Sigma7Model::Default().p_center_O(); }

DeviceCommand Command(const Eigen::Vector3d& f, const Eigen::Vector3d& tau = Eigen::Vector3d::Zero(),
                      double gripper = 0) {
  DeviceCommand c;
  c.f_O = f;
  c.tau_O = tau;
  c.gripper_force_n = gripper;
  return c;
}

class DhdDeviceTest : public ::testing::Test {
 protected:
  FakeSdk fake_{FAKE_DHD_LIBRARY};
  double now_s_ = 0;
  // One tick of the loop with a fixed command: read, write.
  DeviceWriteReport Tick(HapticDevice& device, const DeviceCommand& command) {
    now_s_ += kTick;
    device.Read(now_s_);
    return device.Write(command);
  }
};

TEST_F(DhdDeviceTest, OpensTheFirstSigma7AndReportsItsTypeSerialAndTheSdkVersion) {
  const int types[] = {33, dhd::kDeviceSigma331};  // an omega.3 first, then the sigma.7
  const int serials[] = {11, 1234};
  fake_.set_devices(2, types, serials);
  DhdOptions options = FakeOptions();
  options.velocity_window_ms = 5;
  {
    auto device = DhdDevice::Open(options);
    EXPECT_EQ(device->info().id, 1);
    EXPECT_EQ(device->info().system_type, dhd::kDeviceSigma331);
    EXPECT_EQ(device->info().system_name, "sigma.7");
    EXPECT_EQ(device->info().serial, 1234);
    EXPECT_EQ(device->info().sdk_version, "3.99.0.1");
    EXPECT_EQ(device->info().library_path, FAKE_DHD_LIBRARY);
    EXPECT_NE(device->Describe().find("sigma.7 (type 104) serial 1234, SDK 3.99.0.1"), std::string::npos);
    const FakeDhdState s = fake_.State();
    EXPECT_EQ(s.open_devices, 1);  // the omega.3 was closed again
    EXPECT_EQ(s.linear_window_ms, 5);
    EXPECT_EQ(s.angular_window_ms, 5);
    EXPECT_EQ(s.forces_enabled, 0);
    EXPECT_FALSE(device->forces_enabled());
    EXPECT_EQ(device->EnableForces(true), DeviceStatus::kOk);
    EXPECT_EQ(fake_.State().forces_enabled, 1);
  }
  EXPECT_EQ(fake_.State().open_devices, 0);  // closed on destruction
  EXPECT_EQ(fake_.State().forces_enabled, 0);
}

TEST_F(DhdDeviceTest, ChoosesBySerialOrIndexAndRefusesWhatIsNotASigma7) {
  const int types[] = {33, dhd::kDeviceSigma331Left};
  const int serials[] = {11, 1234};
  fake_.set_devices(2, types, serials);
  DhdOptions o = FakeOptions();
  o.serial = 1234;
  EXPECT_EQ(DhdDevice::Open(o)->info().id, 1);
  o.serial = -1;
  o.index = 1;
  EXPECT_EQ(DhdDevice::Open(o)->info().system_name, "sigma.7 left");
  o.index = 0;
  EXPECT_NE(OpenError(o).find("is a omega.3 (type 33), not a sigma.7"), std::string::npos);
  o.index = 3;
  EXPECT_NE(OpenError(o).find("device index 3 asked for, but 2 device(s)"), std::string::npos);
  o.index = -1;
  o.serial = 999;
  EXPECT_NE(OpenError(o).find("serial 999"), std::string::npos);
  EXPECT_EQ(fake_.State().open_devices, 0);  // nothing left open by the failures

  fake_.set_devices(1, types, serials);
  EXPECT_NE(OpenError(FakeOptions()).find("no sigma.7 among 1 device(s); index 0: omega.3 (type 33)"),
            std::string::npos);
  fake_.set_devices(0, types, serials);
  EXPECT_NE(OpenError(FakeOptions()).find("no Force Dimension device is connected"), std::string::npos);
}

TEST_F(DhdDeviceTest, ReadsThePoseVelocitiesButtonsAndGripper) {
  auto device = DhdDevice::Open(FakeOptions());
  fake_.set_hand_target(Centre().x(), Centre().y() + 0.01, Centre().z());
  for (int k = 0; k < 200; ++k) Tick(*device, DeviceCommand{});  // 50 ms into the hand's move
  const DeviceState& s = device->Read(now_s_ += kTick);
  ASSERT_TRUE(s.ok());
  EXPECT_TRUE(s.presence());  // the fake's button 0 is held
  EXPECT_NEAR((s.X_OH.translation() - fake_.Position()).norm(), 0, 1e-12);
  const FakeDhdState f = fake_.State();
  EXPECT_NEAR((s.v_O - Eigen::Vector3d(f.v[0], f.v[1], f.v[2])).norm(), 0, 1e-12);
  EXPECT_GT(s.v_O.y(), 0);  // the hand moves the handle toward +y
  EXPECT_TRUE(s.X_OH.linear().isUnitary(1e-9));
  EXPECT_DOUBLE_EQ(s.gripper_angle_rad, 0.3);
}

TEST_F(DhdDeviceTest, ClosedLoopThroughTheWallsStopsTheHandAtTheBoundary) {
  // The RSR boundary 5 mm ahead of the handle along +x (the HC → RSR map is a pure offset, scale 1); the hand pulls
  // 15 mm ahead, 10 mm past the wall.
  const Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  const double reach = ReachAlongAxis(testing::Rsr(), testing::Home(), axis, false, 0.3);
  ASSERT_GT(reach, 0.01);
  HcToRsrMap map;
  map.X_FM_anchor = testing::Translated(testing::Home(), (reach - 0.005) * axis);
  map.X_OH_anchor.translation() = Centre();
  auto renderer = MakeRenderer("proxy", testing::Config(), testing::Rsr(), map, 1.0 / kTick);
  renderer->Reset(map.X_OH_anchor);

  auto device = DhdDevice::Open(FakeOptions());
  ASSERT_EQ(device->EnableForces(true), DeviceStatus::kOk);
  const Eigen::Vector3d target = Centre() + 0.015 * axis;
  fake_.set_hand_target(target.x(), target.y(), target.z());
  HapticOutput out;
  int contact_ticks = 0;
  for (int k = 0; k < 8000; ++k) {  // 2 s
    now_s_ += kTick;
    const DeviceState& s = device->Read(now_s_);
    ASSERT_TRUE(s.ok()) << ToString(s.status);
    HapticInput in;
    in.X_OH = s.X_OH;
    in.v_O = s.v_O;
    in.w_O = s.w_O;
    renderer->Tick(in, out);
    contact_ticks += out.status == HapticStatus::kContact;
    const DeviceWriteReport report = device->Write(Command(out.f_O, out.tau_O));
    ASSERT_EQ(report.status, DeviceStatus::kOk);
  }
  const double travel = (fake_.Position() - Centre()).dot(axis);
  EXPECT_GT(contact_ticks, 0);
  EXPECT_EQ(out.status, HapticStatus::kContact);
  EXPECT_LT(fake_.Force().dot(axis), -1.0);  // the force the fake received points back, out of the wall
  // The hand stops near the boundary, well short of its 15 mm target (the boundary is oblique there, so the hand
  // slides a little along it), and at rest the received wall force balances the hand's spring: the wall holds it.
  EXPECT_GT(travel, 0.004);
  EXPECT_LT(travel, 0.010);
  const Eigen::Vector3d f_hand = HandParams{}.stiffness_n_per_m * (target - fake_.Position());
  EXPECT_LT((fake_.Force() + f_hand).norm(), 0.3);
  // Without the walls the same hand goes on to its target.
  for (int k = 0; k < 8000; ++k) Tick(*device, DeviceCommand{});
  EXPECT_NEAR((fake_.Position() - Centre()).dot(axis), 0.015, 0.001);
}

TEST_F(DhdDeviceTest, TheSigma7LimitsApplyBeforeTheSdk) {
  auto device = DhdDevice::Open(FakeOptions());
  device->EnableForces(true);
  const DeviceWriteReport r = Tick(*device, Command({30, 0, 40}, {0, -1, 0}, 12));
  EXPECT_TRUE(r.clamped);
  const FakeDhdState s = fake_.State();
  const Eigen::Vector3d f(s.f[0], s.f[1], s.f[2]), tau(s.tau[0], s.tau[1], s.tau[2]);
  EXPECT_NEAR(f.norm(), 20.0, 1e-12);  // sigma.7 peak (haptic_device.h)
  EXPECT_NEAR(f.x() / f.z(), 0.75, 1e-12);
  EXPECT_NEAR(tau.y(), -0.4, 1e-12);
  EXPECT_DOUBLE_EQ(s.gripper_force, 8.0);
}

TEST_F(DhdDeviceTest, UnpluggedMidRunIsDeviceLostWithZeroForce) {
  auto device = DhdDevice::Open(FakeOptions());
  device->EnableForces(true);
  for (int k = 0; k < 10; ++k) ASSERT_FALSE(Tick(*device, Command({3, 0, 0})).zeroed);
  const Eigen::Isometry3d last_good = device->state().X_OH;
  fake_.unplug();
  const DeviceWriteReport r = Tick(*device, Command({3, 0, 0}));
  EXPECT_EQ(device->state().status, DeviceStatus::kDeviceLost);
  EXPECT_EQ(device->last_sdk_error(), dhd::kErrorNoDeviceFound);
  EXPECT_TRUE(r.zeroed);
  EXPECT_EQ(r.status, DeviceStatus::kDeviceLost);
  EXPECT_FALSE(device->state().presence());
  EXPECT_TRUE(device->state().X_OH.isApprox(last_good));  // nothing downstream jumps
}

TEST_F(DhdDeviceTest, TimeoutsAndCommErrorsAreStatusesAndZeroTheForceUntilAGoodRead) {
  auto device = DhdDevice::Open(FakeOptions());
  device->EnableForces(true);
  Tick(*device, Command({3, 0, 0}));
  EXPECT_DOUBLE_EQ(fake_.Force().x(), 3.0);

  fake_.fail_next(1, dhd::kErrorTimeout);  // the read fails, the write goes through (with zero)
  DeviceWriteReport r = Tick(*device, Command({3, 0, 0}));
  EXPECT_EQ(device->state().status, DeviceStatus::kTimeout);
  EXPECT_TRUE(r.zeroed);
  EXPECT_EQ(r.status, DeviceStatus::kOk);
  EXPECT_EQ(fake_.Force(), Eigen::Vector3d::Zero());

  fake_.fail_next(1, dhd::kErrorCom);
  r = Tick(*device, Command({3, 0, 0}));
  EXPECT_EQ(device->state().status, DeviceStatus::kCommError);
  EXPECT_EQ(fake_.Force(), Eigen::Vector3d::Zero());

  r = Tick(*device, Command({3, 0, 0}));  // recovered
  EXPECT_TRUE(device->state().ok());
  EXPECT_FALSE(r.zeroed);
  EXPECT_DOUBLE_EQ(fake_.Force().x(), 3.0);

  // A failure on the write itself is reported too.
  device->Read(now_s_ += kTick);
  fake_.fail_next(1, dhd::kErrorTimeout);
  EXPECT_EQ(device->Write(Command({3, 0, 0})).status, DeviceStatus::kTimeout);
}

TEST_F(DhdDeviceTest, NanReadingsAreInvalidAndZeroTheForce) {
  auto device = DhdDevice::Open(FakeOptions());
  device->EnableForces(true);
  Tick(*device, Command({3, 0, 0}));
  const Eigen::Isometry3d last_good = device->state().X_OH;
  fake_.nan_next(2);
  for (int k = 0; k < 2; ++k) {
    const DeviceWriteReport r = Tick(*device, Command({3, 0, 0}));
    EXPECT_EQ(device->state().status, DeviceStatus::kInvalidReading);
    EXPECT_TRUE(r.zeroed);
    EXPECT_EQ(fake_.Force(), Eigen::Vector3d::Zero());
    EXPECT_TRUE(device->state().X_OH.matrix().allFinite());
    EXPECT_TRUE(device->state().X_OH.isApprox(last_good));
  }
  Tick(*device, Command({3, 0, 0}));
  EXPECT_TRUE(device->state().ok());
  EXPECT_DOUBLE_EQ(fake_.Force().x(), 3.0);
}

TEST_F(DhdDeviceTest, SdkErrorCodesMapToDeviceStatuses) {
  EXPECT_EQ(DeviceStatusFromDhdError(dhd::kErrorTimeout), DeviceStatus::kTimeout);
  EXPECT_EQ(DeviceStatusFromDhdError(dhd::kErrorCom), DeviceStatus::kCommError);
  EXPECT_EQ(DeviceStatusFromDhdError(dhd::kErrorNoDeviceFound), DeviceStatus::kDeviceLost);
  EXPECT_EQ(DeviceStatusFromDhdError(dhd::kErrorNotAvailable), DeviceStatus::kDeviceLost);
  EXPECT_EQ(DeviceStatusFromDhdError(dhd::kErrorDeviceNotReady), DeviceStatus::kDeviceLost);
  EXPECT_EQ(DeviceStatusFromDhdError(dhd::kError), DeviceStatus::kCommError);
}

TEST_F(DhdDeviceTest, ALibraryMissingAFunctionIsRefusedNamingIt) {
  DhdOptions o;
  o.library_path = FAKE_DHD_NO_FORCE_LIBRARY;
  const std::string error = OpenError(o);
  EXPECT_NE(error.find("'dhdSetForceAndTorqueAndGripperForce' is missing"), std::string::npos) << error;
  EXPECT_NE(error.find(FAKE_DHD_NO_FORCE_LIBRARY), std::string::npos) << error;
}

TEST(DhdDeviceLibrary, NoLibraryIsAnErrorNamingEveryPathTried) {
  DhdOptions o;
  o.library_path = "/nonexistent/fd/libdhd.so";
  std::string error = OpenError(o);
  EXPECT_NE(error.find("the Force Dimension SDK (libdhd) not found"), std::string::npos) << error;
  EXPECT_NE(error.find("/nonexistent/fd/libdhd.so"), std::string::npos) << error;

  if (void* real = dlopen("libdhd.so", RTLD_NOW | RTLD_LOCAL)) {  // a real SDK on this machine would be found
    dlclose(real);
    GTEST_SKIP() << "a libdhd.so is installed; the search would find it";
  }
  setenv("ROBOSSIS_DHD_LIBRARY", "/nonexistent/env/libdhd.so", 1);
  error = OpenError(DhdOptions{});
  unsetenv("ROBOSSIS_DHD_LIBRARY");
  EXPECT_NE(error.find("/nonexistent/env/libdhd.so"), std::string::npos) << error;
  EXPECT_NE(error.find("libdhd.so.3"), std::string::npos) << error;
  EXPECT_NE(error.find("/usr/local/lib/libdhd.so"), std::string::npos) << error;
}

TEST_F(DhdDeviceTest, TheEnvironmentVariablePointsAtTheLibrary) {
  setenv("ROBOSSIS_DHD_LIBRARY", FAKE_DHD_LIBRARY, 1);
  std::unique_ptr<DhdDevice> device;
  EXPECT_NO_THROW(device = DhdDevice::Open(DhdOptions{}));
  unsetenv("ROBOSSIS_DHD_LIBRARY");
  ASSERT_NE(device, nullptr);
  EXPECT_EQ(device->info().library_path, FAKE_DHD_LIBRARY);
}

TEST_F(DhdDeviceTest, TheFactorySpecReadsDhdYamlAndTakesTheRuntimeLimits) {
  EXPECT_TRUE(IsDhdDeviceSpec("dhd"));
  EXPECT_TRUE(IsDhdDeviceSpec("dhd:serial=1"));
  EXPECT_FALSE(IsDhdDeviceSpec("dhdx"));
  EXPECT_FALSE(IsDhdDeviceSpec("sim"));
  DeviceLimits limits;
  limits.max_force_n = 12;
  auto device = OpenDhdDevice(std::string("dhd:lib=") + FAKE_DHD_LIBRARY + ",serial=1234", limits);
  EXPECT_EQ(device->limits().max_force_n, 12);
  const int window_ms = DhdOptionsFromYaml(DefaultDataDir() / "config" / "dhd.yaml").velocity_window_ms;
  EXPECT_EQ(fake_.State().linear_window_ms, window_ms);
  device->EnableForces(true);
  Tick(*device, Command({30, 0, 0}));
  EXPECT_DOUBLE_EQ(fake_.Force().x(), 12.0);
}

TEST_F(DhdDeviceTest, ReadAndWriteDoNotAllocate) {
  auto device = DhdDevice::Open(FakeOptions());
  device->EnableForces(true);
  Tick(*device, Command({1, 0, 0}));
  robossis::testing::AllocationCounter counter;
  for (int k = 0; k < 200; ++k) Tick(*device, Command({1, 0, 0}, {0, 0, 0.01}, 0.5));
  fake_.fail_next(1, dhd::kErrorTimeout);
  Tick(*device, Command({1, 0, 0}));
  EXPECT_EQ(counter.count(), 0u);
}

TEST_F(DhdDeviceTest, WithoutLibdrdThereIsNoHold) {
  auto device = DhdDevice::Open(FakeOptions());
  EXPECT_FALSE(device->info().hold_available);
  EXPECT_EQ(device->HoldHere(), DeviceStatus::kNotOpen);
  EXPECT_EQ(device->HoldAt(Centre()), DeviceStatus::kNotOpen);
  EXPECT_FALSE(device->holding());
}

TEST(DhdDeviceHold, TheRegulationHoldsTheHandleAgainstTheHandAndReleasesIt) {
  FakeSdk fake(FAKE_DRD_LIBRARY);  // libdrd carries libdhd: one SDK instance
  DhdOptions o;
  o.enable_hold = true;
  o.drd_library_path = FAKE_DRD_LIBRARY;
  auto device = DhdDevice::Open(o);
  EXPECT_TRUE(device->info().hold_available);
  EXPECT_EQ(device->info().library_path, FAKE_DRD_LIBRARY);
  const Eigen::Vector3d hold = Centre() + Eigen::Vector3d(0.01, 0, 0);
  const Eigen::Vector3d pull = Centre() + Eigen::Vector3d(0.03, 0, 0);
  fake.set_hand_target(pull.x(), pull.y(), pull.z());
  ASSERT_EQ(device->HoldAt(hold), DeviceStatus::kOk);
  EXPECT_TRUE(device->holding());
  double now_s = 0;
  for (int k = 0; k < 8000; ++k) {
    device->Read(now_s += kTick);
    device->Write(Command({5, 0, 0}));  // the runtime keeps ticking; the regulation owns the motors
  }
  // The hand's pull at the hold (400 N/m · 20 mm = 8 N) against the fake regulation's 2000 N/m: 4 mm.
  EXPECT_NEAR((fake.Position() - hold).norm(), 0.004, 0.001);
  EXPECT_EQ(fake.State().force_writes_held, 0);  // the back end sent nothing while held

  ASSERT_EQ(device->ReleaseHold(), DeviceStatus::kOk);
  EXPECT_FALSE(device->holding());
  EXPECT_EQ(fake.State().drd_running, 0);
  EXPECT_EQ(fake.State().forces_enabled, 0);  // the runtime had not enabled forces
  for (int k = 0; k < 8000; ++k) {
    device->Read(now_s += kTick);
    device->Write(DeviceCommand{});
  }
  EXPECT_NEAR((fake.Position() - pull).norm(), 0, 0.001);  // released: the hand takes the handle

  ASSERT_EQ(device->HoldHere(), DeviceStatus::kOk);
  const Eigen::Vector3d here = fake.Position();
  for (int k = 0; k < 400; ++k) device->Read(now_s += kTick);
  EXPECT_NEAR((fake.Position() - here).norm(), 0, 0.001);

  // A new target for the running hold, then the device lost under it: a status, and the hold is off.
  ASSERT_EQ(device->HoldAt(hold), DeviceStatus::kOk);
  for (int k = 0; k < 8000; ++k) device->Read(now_s += kTick);
  EXPECT_NEAR((fake.Position() - hold).norm(), 0.004, 0.001);
  fake.unplug();
  EXPECT_EQ(device->HoldAt(Centre()), DeviceStatus::kDeviceLost);
  EXPECT_FALSE(device->holding());
}

}  // namespace
}  // namespace robossis::haptics
