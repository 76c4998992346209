// The panel's leader side alone, on an in-process link and a simulated clock with a scripted follower status: it
// sends one set-point per tick, without presence while idle, with presence along the eq. 9 path while a jog runs,
// with strictly increasing sequences stamped by the shared clock, and starts a new leader session after the
// follower was unpowered or another leader sent the set-points.

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "src/core/rt/clock.h"
#include "src/panel/jog_player.h"
#include "src/teleop/in_process_link.h"

namespace robossis::panel {
namespace {

using teleop::OperatingState;

class JogPlayerTest : public ::testing::Test {
 protected:
  void Follower(OperatingState state, double z_m) {
    teleop::FollowerStatusMessage status;
    status.sequence = ++status_sequence_;
    status.state = state;
    status.p_FM = {0, 0, z_m};
    link_.PublishStatus(status);
  }
  teleop::SetPointMessage TickAndTake() {
    clock_.AdvanceNs(1'000'000);  // 1 kHz
    player_.Tick();
    teleop::SetPointMessage message;
    std::int64_t arrival_ns = 0;
    EXPECT_TRUE(link_.TakeSetPoint(message, arrival_ns));
    EXPECT_EQ(arrival_ns, static_cast<std::int64_t>(std::llround(clock_.NowS() * 1e9)));
    return message;
  }

  rt::SimulatedClock clock_;
  teleop::InProcessLink link_{clock_};
  JogPlayer player_{link_, clock_, 1e-3};
  std::uint64_t status_sequence_ = 0;
};

TEST_F(JogPlayerTest, SendsNothingBeforeTheFollowerSpeaks) {
  clock_.AdvanceNs(1'000'000);
  player_.Tick();
  teleop::SetPointMessage message;
  std::int64_t arrival_ns = 0;
  EXPECT_FALSE(link_.TakeSetPoint(message, arrival_ns));
  EXPECT_FALSE(player_.StartMove(Eigen::Vector3d(0, 0, 0.001), Eigen::Vector3d::Zero(), 1));
}

TEST_F(JogPlayerTest, PlaysAJogAsPresenceSetPointsAlongEq9AndHoldsWithoutPresenceAfterIt) {
  Follower(OperatingState::kReady, 0.28);
  teleop::SetPointMessage idle = TickAndTake();
  EXPECT_EQ(idle.flags, 0);
  EXPECT_DOUBLE_EQ(idle.p_FM[2], 0.28);
  ASSERT_TRUE(player_.StartMove(Eigen::Vector3d(0, 0, 0.005), Eigen::Vector3d::Zero(), 1.0));
  EXPECT_FALSE(player_.StartMove(Eigen::Vector3d(0, 0, 0.005), Eigen::Vector3d::Zero(), 1.0));  // one at a time
  std::uint64_t sequence = idle.sequence;
  double z_half = 0;
  for (int i = 1; i <= 1000; ++i) {
    const teleop::SetPointMessage m = TickAndTake();
    EXPECT_GT(m.sequence, sequence);
    sequence = m.sequence;
    EXPECT_EQ(m.leader_session, idle.leader_session);
    EXPECT_EQ(m.flags, teleop::kSetPointPresence);
    EXPECT_EQ(m.stamp_ns, static_cast<std::int64_t>(std::llround(clock_.NowS() * 1e9)));
    if (i == 500) z_half = m.p_FM[2];
  }
  EXPECT_NEAR(z_half - 0.28, 0.0025, 1e-6);  // eq. 9 at half time: half the amount
  const teleop::SetPointMessage after = TickAndTake();
  EXPECT_EQ(after.flags, 0);
  EXPECT_NEAR(after.p_FM[2], 0.285, 1e-12);
  EXPECT_FALSE(player_.moving());
}

// A late tick (the leader-side loop preempted for 20 ms) lags the move: its next set-point is one set-point period
// further along the path, not 20 ms, since the follower judges the step over the one sequence step.
TEST_F(JogPlayerTest, ALateTickLagsTheMoveInsteadOfJumpingAlongIt) {
  Follower(OperatingState::kReady, 0.28);
  TickAndTake();
  ASSERT_TRUE(player_.StartMove(Eigen::Vector3d(0, 0, 0.005), Eigen::Vector3d::Zero(), 1.0));
  double z = TickAndTake().p_FM[2];
  double largest_step_m = 0;
  int ticks = 1;
  for (; player_.moving() && ticks < 2000; ++ticks) {
    if (ticks == 400) clock_.AdvanceNs(20'000'000);  // the stall, mid-move where the path is fastest
    const double next = TickAndTake().p_FM[2];
    largest_step_m = std::max(largest_step_m, next - z);
    z = next;
  }
  // eq. 9's peak speed is pi/2 x 5 mm / 1 s = 7.85 mm/s: at most 7.85 um per 1 ms set-point.
  EXPECT_LT(largest_step_m, 0.5 * M_PI * 0.005 * 1e-3 * (1 + 1e-9));
  EXPECT_EQ(ticks, 1000);  // one set-point per period of the move, the stall included
  EXPECT_NEAR(z, 0.285, 1e-12);
}

TEST_F(JogPlayerTest, AnUnpoweredFollowerDropsTheMoveAndResynchronisesInANewSession) {
  Follower(OperatingState::kReady, 0.28);
  const teleop::SetPointMessage first = TickAndTake();
  ASSERT_TRUE(player_.StartMove(Eigen::Vector3d(0, 0, 0.005), Eigen::Vector3d::Zero(), 1.0));
  for (int i = 0; i < 300; ++i) TickAndTake();
  Follower(OperatingState::kEStop, 0.2812);
  EXPECT_EQ(TickAndTake().flags, 0);
  EXPECT_FALSE(player_.moving());
  Follower(OperatingState::kReady, 0.2812);
  const teleop::SetPointMessage resumed = TickAndTake();
  EXPECT_NE(resumed.leader_session, first.leader_session);
  EXPECT_DOUBLE_EQ(resumed.p_FM[2], 0.2812);
  EXPECT_EQ(resumed.flags, 0);
}

// After another leader (the panel's haptic mode) sent the set-points, the player sends nothing until the follower's
// next status, then holds that pose in a new leader session, and jogs from there.
TEST_F(JogPlayerTest, AResyncHoldsTheNextStatusPoseInANewSession) {
  Follower(OperatingState::kReady, 0.28);
  const teleop::SetPointMessage before = TickAndTake();
  player_.Resync();
  clock_.AdvanceNs(1'000'000);
  player_.Tick();
  teleop::SetPointMessage message;
  std::int64_t arrival_ns = 0;
  EXPECT_FALSE(link_.TakeSetPoint(message, arrival_ns));  // no status since: nothing to hold yet
  Follower(OperatingState::kEnabled, 0.29);  // where the hand left the robot
  const teleop::SetPointMessage after = TickAndTake();
  EXPECT_NE(after.leader_session, before.leader_session);
  EXPECT_DOUBLE_EQ(after.p_FM[2], 0.29);
  EXPECT_EQ(after.flags, 0);
  Follower(OperatingState::kReady, 0.29);
  TickAndTake();
  EXPECT_TRUE(player_.StartMove(Eigen::Vector3d(0, 0, 0.001), Eigen::Vector3d::Zero(), 1));
}

}  // namespace
}  // namespace robossis::panel
