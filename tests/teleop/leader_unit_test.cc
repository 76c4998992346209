// The leader unit: presence-gated tracking, set-points that stay feasible (exact IK) for every rendering method
// even when a fast hand goes far outside the workspace, device failures (zero force, a latched fault, a hold
// request), the end of a replay (a hold), and no allocation per tick.

#include <utility>

#include <gtest/gtest.h>

#include "haptics/device/device_factory.h"
#include "haptics/device/simulated_device.h"
#include "robot/rsr_kinematics.h"
#include "src/core/rt/periodic_loop.h"
#include "src/teleop/leader_unit.h"
#include "src/teleop/teleop_session.h"
#include "tests/support/alloc_counter.h"
#include "tests/teleop/teleop_fixture.h"

namespace robossis::teleop {
namespace {

using namespace testing;

struct Harness {
  Harness(const std::string& device_spec, const std::string& method, transfer::TransferConfig transfer = Transfer(),
          std::size_t keep = 40000, LeaderConfig leader = Leader())
      : config(std::move(leader)),
        device(haptics::MakeDevice(device_spec, Sigma7(), Haptics(), config.device, config.sim_script)),
        renderer(Renderer(method, config.rate_hz)),
        link(keep),
        unit(config, transfer, Rsr(), *device, *renderer, link, Rsr().geometry().X_FM_home, 7) {
    device->EnableForces(true);
  }
  void Run(double seconds) {
    rt::LoopOptions o;
    o.period_ns = static_cast<std::int64_t>(1e9 / config.rate_hz);
    rt::RunSimulated(clock, {{&unit, o}}, seconds, [this](double) {
      LeaderTickRecord r;
      while (unit.records().TryPop(r)) {
      }
      return true;
    });
  }
  haptics::SimulatedDevice& sim() { return dynamic_cast<haptics::SimulatedDevice&>(*device); }
  LeaderConfig config;
  std::unique_ptr<haptics::HapticDevice> device;
  std::unique_ptr<haptics::HapticRenderer> renderer;
  RecordingLeaderLink link;
  LeaderUnit unit;
  rt::SimulatedClock clock;
};

// Caps far above the paper's 10 mm/s and 1°/s, so that the set-point follows the fast hand almost one to one and
// is driven far outside the workspace: the boundary must hold however fast the transfer lets the hand go.
transfer::TransferConfig FastCaps() {
  transfer::TransferConfig t = Transfer();
  t.caps.max_linear_speed_m_s = 0.25;
  t.caps.max_angular_speed_rad_s = 60 * 3.14159265358979 / 180;
  return t;
}

TEST(LeaderUnitTest, TracksTheHandWithPresenceAndSendsFeasibleSetPoints) {
  Harness h("sim", "proxy-safe");
  h.Run(2.0);
  EXPECT_EQ(h.unit.state(), LeaderState::kTracking);
  ASSERT_EQ(h.link.count, 2000u);  // one per 1 ms transfer period
  std::uint64_t previous = 0;
  double moved = 0;
  for (const SetPointMessage& m : h.link.sent) {
    EXPECT_GT(m.sequence, previous);
    previous = m.sequence;
    EXPECT_EQ(m.leader_session, 7u);
    EXPECT_TRUE(m.flags & kSetPointPresence);
    const Eigen::Isometry3d X = PoseFromArrays(m.p_FM, m.q_FM);
    EXPECT_TRUE(robot::IsPoseFeasible(Rsr(), X));
    moved = std::max(moved, (X.translation() - Rsr().geometry().X_FM_home.translation()).norm());
  }
  EXPECT_GT(moved, 0.005);  // the circle moved the set-point (at the 10 mm/s cap)
}

// The operator's clutch (a control panel's Clutch button): with the hand present, the set-points carry presence and
// the clutch flag and stop moving, no force is displayed; closed again, tracking resumes from where it stopped.
TEST(LeaderUnitTest, TheOperatorsClutchHoldsTheSetPointWithPresenceAndNoForce) {
  Harness h("sim", "proxy-safe");
  h.Run(0.4);
  h.unit.RequestClutch(true);
  h.Run(0.2);  // the transfer's filters settle near where the hand let go
  const Eigen::Vector3d held = PoseFromArrays(h.link.last.p_FM, h.link.last.q_FM).translation();
  h.Run(0.4);  // the hand goes on along its circle, ~19 mm
  EXPECT_EQ(h.unit.state(), LeaderState::kTracking);
  EXPECT_TRUE(h.link.last.flags & kSetPointPresence);
  EXPECT_TRUE(h.link.last.flags & kSetPointClutched);
  EXPECT_LT((PoseFromArrays(h.link.last.p_FM, h.link.last.q_FM).translation() - held).norm(), 0.5e-3);
  LeaderTickRecord r;
  ASSERT_TRUE(h.unit.latest().Read(r));
  EXPECT_EQ(Eigen::Vector3d(r.f_O[0], r.f_O[1], r.f_O[2]).norm(), 0.0);
  h.unit.RequestClutch(false);
  h.Run(0.5);
  EXPECT_TRUE(h.link.last.flags & kSetPointPresence);
  EXPECT_FALSE(h.link.last.flags & kSetPointClutched);
  EXPECT_GT((PoseFromArrays(h.link.last.p_FM, h.link.last.q_FM).translation() - held).norm(), 2e-3);
}

class FastHandEveryMethod : public ::testing::TestWithParam<std::string> {};

TEST_P(FastHandEveryMethod, SetPointsNeverLeaveTheWorkspace) {
  Harness h("replay:" + FastHand().string(), GetParam(), FastCaps(), 20000);
  h.Run(17.0);
  EXPECT_EQ(h.unit.state(), LeaderState::kEnded);
  ASSERT_GT(h.link.sent.size(), 16000u);
  std::size_t infeasible = 0;
  for (const SetPointMessage& m : h.link.sent) {
    if (!robot::IsPoseFeasible(Rsr(), PoseFromArrays(m.p_FM, m.q_FM))) ++infeasible;
  }
  EXPECT_EQ(infeasible, 0u);
  // The test can fail: the hand did drive the set-point into the boundary, many times.
  EXPECT_GT(h.unit.counters().stopped_at_boundary, 1000u) << GetParam();
  EXPECT_EQ(h.unit.counters().nonfinite_outputs, 0u);
  EXPECT_GT(h.unit.counters().max_force_n, 1.0);  // and the walls pushed back
}

INSTANTIATE_TEST_SUITE_P(Methods, FastHandEveryMethod, ::testing::ValuesIn(haptics::KnownMethods()),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (char& c : n) if (c == '-') c = '_';
                           return n;
                         });

TEST(LeaderUnitTest, DeviceFailureZeroesTheForceLatchesAFaultAndEStops) {
  Harness h("sim", "proxy-safe");
  h.Run(0.5);
  ASSERT_EQ(h.unit.state(), LeaderState::kTracking);
  EXPECT_EQ(h.link.estops, 0);
  h.sim().Inject(haptics::InjectedFault::kNonFinite, 5);
  h.Run(0.2);
  EXPECT_EQ(h.unit.state(), LeaderState::kDeviceFault);  // latched though the reads are good again
  EXPECT_EQ(h.unit.counters().device_failures, 1u);
  EXPECT_EQ(h.link.estops, 1);  // once per failure, however many failed reads
  EXPECT_EQ(h.sim().last_force_O(), Eigen::Vector3d::Zero());
  EXPECT_TRUE(h.link.last.flags & kSetPointDeviceFault);
  EXPECT_FALSE(h.link.last.flags & kSetPointPresence);
  // The set-point comes to rest (the transfer's filters decelerate within the caps: under 0.1 mm in 0.2 s).
  h.Run(0.3);
  const Eigen::Isometry3d held = PoseFromArrays(h.link.last.p_FM, h.link.last.q_FM);
  h.Run(0.2);
  EXPECT_LT((PoseFromArrays(h.link.last.p_FM, h.link.last.q_FM).translation() - held.translation()).norm(), 1e-4);
  h.unit.RequestReset();
  h.Run(0.1);
  EXPECT_EQ(h.unit.state(), LeaderState::kTracking);
  EXPECT_TRUE(h.link.last.flags & kSetPointPresence);
}

TEST(LeaderUnitTest, StaleAndFailedReadsFaultToo) {
  for (auto fault : {haptics::InjectedFault::kStale, haptics::InjectedFault::kFailedRead}) {
    Harness h("sim", "pointcloud-safe");
    h.Run(0.1);
    h.sim().Inject(fault, 1);
    h.Run(0.01);
    EXPECT_EQ(h.unit.state(), LeaderState::kDeviceFault);
    EXPECT_EQ(h.sim().last_force_O(), Eigen::Vector3d::Zero());
  }
}

TEST(LeaderUnitTest, EndOfReplayHoldsWithoutPresence) {
  Harness h("replay:" + FastHand().string(), "proxy-safe");
  h.Run(16.5);
  EXPECT_EQ(h.unit.state(), LeaderState::kEnded);
  const SetPointMessage end = h.link.last;
  EXPECT_FALSE(end.flags & kSetPointPresence);
  EXPECT_TRUE(end.flags & kSetPointClutched);
  h.Run(0.5);
  EXPECT_LT((PoseFromArrays(h.link.last.p_FM, h.link.last.q_FM).translation() -
             PoseFromArrays(end.p_FM, end.q_FM).translation()).norm(), 1e-6);
  EXPECT_EQ(h.sim().last_force_O(), Eigen::Vector3d::Zero());
}

TEST(LeaderUnitTest, TickDoesNotAllocate) {
  // As the runtime configures it (TeleopSetup::Load): the set-points within the motors' top speeds too.
  const LeaderConfig runtime = TeleopSetup::Load(DefaultDataDir(), Rsr(), Sigma7()).leader;
  ASSERT_TRUE(runtime.max_joint_speed.allFinite());
  for (const std::string& method : haptics::KnownMethods()) {
    Harness h("replay:" + FastHand().string(), method, FastCaps(), 0, runtime);
    rt::SimulatedClock& clock = h.clock;
    for (int k = 0; k < 200; ++k) {  // warm up
      clock.AdvanceNs(1'000'000);
      h.unit.Tick(clock.now_ns());
    }
    LeaderTickRecord r;
    ::robossis::testing::AllocationCounter counter;
    for (int k = 0; k < 3000; ++k) {
      clock.AdvanceNs(1'000'000);
      h.unit.Tick(clock.now_ns());
      h.unit.records().TryPop(r);
    }
    EXPECT_EQ(counter.count(), 0u) << method;
  }
}

}  // namespace
}  // namespace robossis::teleop
