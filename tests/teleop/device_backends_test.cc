// The simulated and replay device back ends: the hand follows its script in simulated time, presence is held while
// the script runs, a replay ends with kEndOfScript, and every injected failure (failed read, NaN, stale sample)
// zeroes the force the device displays.

#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "haptics/device/device_factory.h"
#include "haptics/device/simulated_device.h"
#include "src/core/config.h"
#include "tests/support/alloc_counter.h"

namespace robossis::haptics {
namespace {

const robot::Sigma7Model& Sigma7() {
  static const robot::Sigma7Model m = robot::Sigma7Model::Default();
  return m;
}
const HapticsConfig& Haptics() {
  static const HapticsConfig c = HapticsConfig::FromYaml(DefaultDataDir() / "config" / "haptics.yaml");
  return c;
}

std::filesystem::path WriteCsv(const std::string& name, const std::string& body) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n" << body;
  return path;
}

// Steps the device at 1 kHz for `seconds`, writing `force` each tick; returns the last state.
DeviceState RunDevice(HapticDevice& dev, double& t, double seconds, const Eigen::Vector3d& force = Eigen::Vector3d::Zero()) {
  DeviceState s;
  const int n = static_cast<int>(std::lround(seconds * 1000));
  for (int k = 0; k < n; ++k) {
    t += 1e-3;
    s = dev.Read(t);
    DeviceCommand c;
    c.f_O = force;
    dev.Write(c);
  }
  return s;
}

TEST(DeviceBackendsTest, SimHandTracesItsCircleWithPresenceHeld) {
  DeviceScriptOptions o;
  o.sim_radius_m = 0.02;
  o.sim_frequency_hz = 0.5;
  auto dev = MakeDevice("sim", Sigma7(), Haptics(), DeviceLimits{}, o);
  double t = 0;
  const DeviceState s0 = RunDevice(*dev, t, 0.001);
  EXPECT_TRUE(s0.presence());
  EXPECT_LT((s0.X_OH.translation() - Sigma7().p_center_O()).norm(), 1e-3);
  // Half a period later the hand is near the far side of the circle (2 r away), still holding presence.
  const DeviceState s1 = RunDevice(*dev, t, 1.0);
  EXPECT_TRUE(s1.presence());
  EXPECT_NEAR((s1.X_OH.translation() - Sigma7().p_center_O()).norm(), 0.04, 0.01);
}

TEST(DeviceBackendsTest, ReplayFollowsTheRecordingAndEndsWithEndOfScript) {
  // 20 mm along +x in 0.5 s, from the RSR pose (0, 0, 200 mm).
  const auto file = WriteCsv("robossis_replay_test.csv", "0,0,0,200,0,0,0\n0.5,20,0,200,0,0,0\n");
  DeviceScriptOptions o;
  auto dev = MakeDevice("replay:" + file.string(), Sigma7(), Haptics(), DeviceLimits{}, o);
  double t = 0;
  const DeviceState start = RunDevice(*dev, t, 0.001);
  ASSERT_TRUE(start.presence());
  const DeviceState mid = RunDevice(*dev, t, 0.45);
  EXPECT_TRUE(mid.presence());
  const DeviceState end = RunDevice(*dev, t, 1.0);  // well past the end: the hand has settled at the last sample
  EXPECT_EQ(end.status, DeviceStatus::kEndOfScript);
  EXPECT_FALSE(end.presence());
  const double moved = end.X_OH.translation().x() - start.X_OH.translation().x();
  EXPECT_NEAR(moved, 0.020 / o.replay_frame.translation_scale, 0.002);
  std::filesystem::remove(file);
}

TEST(DeviceBackendsTest, AReplayIsPlacedThroughTheSessionsFrameMap) {
  // The same 20 mm along +x of F, with the HC base turned 90° about z from F and a scale of 2: the hand must move
  // R_FOᵀ · (+x) · 20 mm / 2 = 10 mm along −y of O, so that the set-points replay the recorded path in F.
  const auto file = WriteCsv("robossis_replay_frame_test.csv", "0,0,0,200,0,0,0\n0.5,20,0,200,0,0,0\n");
  DeviceScriptOptions o;
  o.replay_frame.R_FO = Eigen::AngleAxisd(EIGEN_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  o.replay_frame.translation_scale = 2.0;
  auto dev = MakeDevice("replay:" + file.string(), Sigma7(), Haptics(), DeviceLimits{}, o);
  double t = 0;
  const DeviceState start = RunDevice(*dev, t, 0.001);
  const DeviceState end = RunDevice(*dev, t, 1.0);
  const Eigen::Vector3d moved = end.X_OH.translation() - start.X_OH.translation();
  EXPECT_NEAR(moved.y(), -0.010, 0.001);
  EXPECT_NEAR(moved.x(), 0.0, 0.001) << "placed without R_FO, the hand would move along +x";
  std::filesystem::remove(file);
}

TEST(DeviceBackendsTest, UnknownDeviceAndBadFileAreNamed) {
  try {
    MakeDevice("dhd9", Sigma7(), Haptics(), DeviceLimits{}, {});
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("dhd9"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("replay:FILE.csv"), std::string::npos);
  }
  const auto bad = WriteCsv("robossis_replay_bad.csv", "0,0,0,200,0,0,0\n0.5,x,0,200,0,0,0\n");
  EXPECT_THROW(MakeDevice("replay:" + bad.string(), Sigma7(), Haptics(), DeviceLimits{}, {}), std::runtime_error);
  std::filesystem::remove(bad);
}

class InjectedFailureTest : public ::testing::TestWithParam<InjectedFault> {};

TEST_P(InjectedFailureTest, ZeroesTheForceUntilAGoodRead) {
  auto dev = MakeDevice("sim", Sigma7(), Haptics(), DeviceLimits{}, {});
  auto& sim = dynamic_cast<SimulatedDevice&>(*dev);
  ASSERT_EQ(dev->EnableForces(true), DeviceStatus::kOk);
  double t = 0;
  const Eigen::Vector3d push(3, 0, 0);
  RunDevice(*dev, t, 0.01, push);
  ASSERT_TRUE(dev->state().ok());
  EXPECT_EQ(sim.last_force_O(), push);

  sim.Inject(GetParam(), 3);
  const Eigen::Vector3d before = dev->state().X_OH.translation();
  for (int k = 0; k < 3; ++k) {
    t += 1e-3;
    const DeviceState& s = dev->Read(t);
    EXPECT_FALSE(s.ok()) << ToString(s.status);
    EXPECT_FALSE(s.presence());
    EXPECT_TRUE(s.X_OH.matrix().allFinite());
    EXPECT_LT((s.X_OH.translation() - before).norm(), 1e-12);  // the last good pose, nothing jumps
    DeviceCommand c;
    c.f_O = push;
    const DeviceWriteReport r = dev->Write(c);
    EXPECT_TRUE(r.zeroed);
    EXPECT_EQ(sim.last_force_O(), Eigen::Vector3d::Zero());
  }
  RunDevice(*dev, t, 0.001, push);
  EXPECT_TRUE(dev->state().ok());
  EXPECT_EQ(sim.last_force_O(), push);
}

INSTANTIATE_TEST_SUITE_P(Faults, InjectedFailureTest,
                         ::testing::Values(InjectedFault::kFailedRead, InjectedFault::kNonFinite,
                                           InjectedFault::kStale));

TEST(DeviceBackendsTest, ReadAndWriteDoNotAllocate) {
  const auto file = WriteCsv("robossis_replay_alloc.csv", "0,0,0,200,0,0,0\n0.5,20,0,200,0,0,10\n");
  for (const std::string& spec : {std::string("sim"), "replay:" + file.string()}) {
    auto dev = MakeDevice(spec, Sigma7(), Haptics(), DeviceLimits{}, {});
    dev->EnableForces(true);
    double t = 0;
    RunDevice(*dev, t, 0.01);
    testing::AllocationCounter counter;
    RunDevice(*dev, t, 0.2, Eigen::Vector3d(1, 0, 0));
    EXPECT_EQ(counter.count(), 0u) << spec;
  }
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace robossis::haptics
