// The leader's walls follow the real robot: while the follower does not follow (not enabled, or silent), the
// leader displays no force, the hand moves nothing, and the set-points move, within the follower's caps, to the
// robot's measured pose; once it follows again, tracking starts from there.

#include <gtest/gtest.h>

#include "haptics/device/device_factory.h"
#include "src/core/rt/periodic_loop.h"
#include "src/teleop/leader_unit.h"
#include "tests/support/alloc_counter.h"
#include "tests/teleop/teleop_fixture.h"

namespace robossis::teleop {
namespace {

using namespace testing;

class LeaderFollowsRobotTest : public ::testing::Test {
 protected:
  LeaderFollowsRobotTest()
      : config_(Leader()),
        device_(haptics::MakeDevice("sim", Sigma7(), Haptics(), config_.device, config_.sim_script)),
        renderer_(Renderer("proxy-safe", config_.rate_hz)),
        link_(20000),
        unit_(config_, transfer_, Rsr(), *device_, *renderer_, link_, Rsr().geometry().X_FM_home, 7) {
    device_->EnableForces(true);
  }
  void Run(double seconds) {
    rt::LoopOptions o;
    o.period_ns = static_cast<std::int64_t>(1e9 / config_.rate_hz);
    rt::RunSimulated(clock_, {{&unit_, o}}, seconds, [this](double) {
      LeaderTickRecord r;
      while (unit_.records().TryPop(r)) {
      }
      return true;
    });
  }
  void Report(OperatingState state, const Eigen::Vector3d& p_FM) {
    link_.follower_speaks = true;
    link_.follower.state = state;
    link_.follower.p_FM = {p_FM.x(), p_FM.y(), p_FM.z()};
    const Eigen::Quaterniond q(Rsr().geometry().X_FM_home.linear());
    link_.follower.q_FM = {q.w(), q.x(), q.y(), q.z()};
  }
  Eigen::Vector3d LastSent() const { return PoseFromArrays(link_.last.p_FM, link_.last.q_FM).translation(); }
  double LastForce() const {
    LeaderTickRecord r;
    EXPECT_TRUE(unit_.latest().Read(r));
    return Eigen::Vector3d(r.f_O[0], r.f_O[1], r.f_O[2]).norm();
  }
  // The largest change between two consecutive set-points from index `from` on.
  double LargestStep(std::size_t from) const {
    double largest = 0;
    for (std::size_t i = std::max<std::size_t>(from, 1); i < link_.sent.size(); ++i) {
      largest = std::max(largest, (PoseFromArrays(link_.sent[i].p_FM, link_.sent[i].q_FM).translation() -
                                   PoseFromArrays(link_.sent[i - 1].p_FM, link_.sent[i - 1].q_FM).translation())
                                      .norm());
    }
    return largest;
  }

  const transfer::TransferConfig transfer_ = Transfer();
  LeaderConfig config_;
  std::unique_ptr<haptics::HapticDevice> device_;
  std::unique_ptr<haptics::HapticRenderer> renderer_;
  RecordingLeaderLink link_;
  LeaderUnit unit_;
  rt::SimulatedClock clock_;
};

TEST_F(LeaderFollowsRobotTest, WhileTheRobotIsNotEnabledTheSetPointsGoToItAndNoForceIsShown) {
  const Eigen::Vector3d home = Rsr().geometry().X_FM_home.translation();
  const Eigen::Vector3d robot = home + Eigen::Vector3d(0.004, 0, 0);  // left 4 mm away, e.g. by an earlier session
  Report(OperatingState::kDisabled, robot);
  Run(1.5);  // the simulated hand moves all along
  EXPECT_LT((LastSent() - robot).norm(), 1e-6);
  EXPECT_EQ(LastForce(), 0.0);
  const double cap_step = transfer_.caps.max_linear_speed_m_s / transfer_.rates.transfer_rate_hz;
  EXPECT_LE(LargestStep(0), cap_step * (1 + 1e-9));  // it went there within the follower's speed cap
  // Enabled: tracking starts from the robot, not from where the leader began.
  const std::size_t resumed = link_.sent.size();
  Report(OperatingState::kEnabled, robot);
  Run(1.0);
  ASSERT_GT(link_.sent.size(), resumed + 10);
  EXPECT_LT((PoseFromArrays(link_.sent[resumed].p_FM, link_.sent[resumed].q_FM).translation() - robot).norm(),
            2 * cap_step);
  EXPECT_LE(LargestStep(resumed), cap_step * (1 + 1e-9));
  EXPECT_GT((LastSent() - robot).norm(), 1e-3);  // the hand moves the robot again
  LeaderTickRecord r;
  ASSERT_TRUE(unit_.latest().Read(r));
  // The walls are rendered where the set-points go: at the robot, plus the hand's motion since.
  EXPECT_LT((Eigen::Vector3d(r.p_goal[0], r.p_goal[1], r.p_goal[2]) - LastSent()).norm(), 1e-3);
}

TEST_F(LeaderFollowsRobotTest, AFollowerThatFallsSilentStopsTheRendering) {
  const Eigen::Vector3d home = Rsr().geometry().X_FM_home.translation();
  Report(OperatingState::kEnabled, home);
  Run(0.5);
  EXPECT_EQ(unit_.state(), LeaderState::kTracking);
  link_.follower_speaks = false;  // the link or the follower is gone
  Run(0.1 + config_.follower_status_timeout_s);
  const Eigen::Vector3d held = LastSent();
  Run(0.5);
  EXPECT_LT((LastSent() - held).norm(), 1e-9);  // the hand moves nothing
  EXPECT_EQ(LastForce(), 0.0);
}

// Following the measured robot, and resuming from it (the walls' map and the proxy reset), allocate nothing either.
TEST(LeaderFollowsRobotAllocationTest, TicksThatFollowTheMeasuredRobotDoNotAllocate) {
  for (const std::string& method : haptics::KnownMethods()) {
    const LeaderConfig config = Leader();
    auto device = haptics::MakeDevice("replay:" + FastHand().string(), Sigma7(), Haptics(), config.device,
                                      config.sim_script);
    device->EnableForces(true);
    auto renderer = Renderer(method, config.rate_hz);
    RecordingLeaderLink link(0);
    LeaderUnit unit(config, Transfer(), Rsr(), *device, *renderer, link, Rsr().geometry().X_FM_home, 7);
    link.follower_speaks = true;
    const Eigen::Vector3d p = Rsr().geometry().X_FM_home.translation() + Eigen::Vector3d(0.002, 0, 0);
    link.follower.p_FM = {p.x(), p.y(), p.z()};
    const Eigen::Quaterniond q(Rsr().geometry().X_FM_home.linear());
    link.follower.q_FM = {q.w(), q.x(), q.y(), q.z()};
    rt::SimulatedClock clock;
    LeaderTickRecord r;
    const auto run = [&](int ticks) {
      for (int k = 0; k < ticks; ++k) {
        // Disabled, then enabled, every 300 ticks: both paths and both edges.
        link.follower.state = (k / 300) % 2 == 0 ? OperatingState::kDisabled : OperatingState::kEnabled;
        clock.AdvanceNs(1'000'000);
        unit.Tick(clock.now_ns());
        unit.records().TryPop(r);
      }
    };
    run(200);  // warm up
    ::robossis::testing::AllocationCounter counter;
    run(2400);
    EXPECT_EQ(counter.count(), 0u) << method;
  }
}

}  // namespace
}  // namespace robossis::teleop
