// The panel's leader side alone, on an in-process link and a simulated clock with a scripted follower status: it
// sends one set-point per tick, without presence while idle, with presence along the eq. 9 path while a jog runs,
// with strictly increasing sequences stamped by the shared clock, and starts a new leader session after the
// follower was unpowered.

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
  JogPlayer player_{link_, clock_};
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

TEST_F(JogPlayerTest, HapticModeSendsPresenceAndTheClutch) {
  Follower(OperatingState::kReady, 0.28);
  TickAndTake();
  player_.SetHaptic(true, false);
  EXPECT_EQ(TickAndTake().flags, teleop::kSetPointPresence);
  player_.SetHaptic(true, true);
  EXPECT_EQ(TickAndTake().flags, teleop::kSetPointPresence | teleop::kSetPointClutched);
  EXPECT_FALSE(player_.StartMove(Eigen::Vector3d(0, 0, 0.001), Eigen::Vector3d::Zero(), 1));
  player_.SetHaptic(false, false);
  EXPECT_EQ(TickAndTake().flags, 0);
}

}  // namespace
}  // namespace robossis::panel
