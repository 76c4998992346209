// Recovery without a jump when the robot moved while its drives were off: the follower unit powers up again from
// where the joints are, however long it was unpowered.

#include <cmath>

#include <gtest/gtest.h>

#include "robot/rsr_kinematics.h"
#include "src/core/config.h"
#include "src/teleop/follower_unit.h"
#include "src/teleop/in_process_link.h"
#include "tests/teleop/follower_fixture.h"
#include "tests/support/alloc_counter.h"

namespace robossis::teleop {
namespace {

constexpr std::int64_t kTickNs = 100'000;  // 10 kHz

// An ideal drive that follows each joint command exactly, whose joints can be pushed while it is unpowered (the
// ring moved by hand, or sagging under a load, while the drives are off).
class PushableFollower final : public robot::Follower {
 public:
  PushableFollower(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM) : model_(model) {
    state_.X_FM = X_FM;
    state_.q = robot::CalcInverseKinematics(model, X_FM).joints.actuated();
    state_.homed = true;
  }
  bool Enable() noexcept override { return state_.enabled = true; }
  void Disable() noexcept override { state_.enabled = false; }
  bool Home() noexcept override { return true; }
  bool MeasuresJoints() const noexcept override { return true; }
  bool ResetFault() noexcept override { return true; }
  void Command(const robot::RsrJointCommand& command) noexcept override {
    if (state_.enabled) state_.q = command.q;
  }
  void Service(double now_s) noexcept override {
    state_.time_s = now_s;
    state_.X_FM = robot::CalcForwardKinematics(model_, state_.q, state_.X_FM).X_FM;
  }
  robot::RsrFollowerState State() const noexcept override { return state_; }

  void Push(int joint, double amount) {
    ASSERT_FALSE(state_.enabled);
    state_.q[joint] += amount;
  }

 private:
  const robot::RsrModel& model_;
  robot::RsrFollowerState state_;
};

class FollowerRecoveryTest : public ::testing::Test, protected ShippedFollowerSetup {
 protected:
  const FollowerConfig config_ = ShippedFollowerConfig();
  rt::SimulatedClock clock_;
  InProcessLink link_{clock_};
  PushableFollower back_end_{model_, home_};
  FollowerUnit unit_{model_, actuation_, config_, back_end_, link_, clock_};
  std::uint64_t sequence_ = 0;
  std::uint64_t session_ = 1;

  void Command(StateCommand c) {
    StateCommandMessage m;
    m.command = c;
    ASSERT_TRUE(link_.operator_commands().Send(m));
  }
  // Runs `seconds` of 10 kHz ticks; a leader holding still at `p_FM` sends a set-point every 10th tick when
  // `sending`. Returns the largest distance the measured ring moved in one tick.
  double Run(double seconds, bool sending, const Eigen::Vector3d& p_FM) {
    double max_step = 0;
    for (int i = 0; i < static_cast<int>(std::llround(seconds * 1e4)); ++i) {
      clock_.AdvanceNs(kTickNs);
      if (sending && i % 10 == 0) {
        SetPointMessage m;
        m.sequence = ++sequence_;
        m.leader_session = session_;
        m.stamp_ns = clock_.now_ns();
        m.p_FM = {p_FM.x(), p_FM.y(), p_FM.z()};
        m.flags = kSetPointPresence;
        link_.SendSetPoint(m);
      }
      const Eigen::Vector3d before = back_end_.State().X_FM.translation();
      unit_.Tick();
      max_step = std::max(max_step, (back_end_.State().X_FM.translation() - before).norm());
    }
    return max_step;
  }
};

TEST_F(FollowerRecoveryTest, PushedWhileUnpoweredItResumesFromWhereTheJointsAre) {
  Command(StateCommand::kEnable);
  Run(0.2, true, home_.translation());
  ASSERT_EQ(unit_.state(), OperatingState::kEnabled);
  // The leader goes away: hold, then the drives are disabled (leader lost).
  Run(1.0, false, home_.translation());
  ASSERT_EQ(unit_.state(), OperatingState::kDisabled);
  // The ring is pushed 0.2 mm along one stroke while the drives are off, and stays off for 2 s more.
  back_end_.Push(robot::StrokeIndex(0), 0.2e-3);
  Run(2.0, false, home_.translation());
  const Eigen::Vector3d pushed = back_end_.State().X_FM.translation();
  // A new leader session, holding still where it believes the robot is; the operator enables.
  session_ = 2;
  Command(StateCommand::kEnable);
  ::robossis::testing::AllocationCounter counter;  // the resync and the resumed ticks allocate nothing
  const double max_step = Run(0.5, true, home_.translation());
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_EQ(unit_.state(), OperatingState::kEnabled);
  // No jump: at most one tick at the linear cap, with a margin for the kinematics' rounding.
  EXPECT_LE(max_step, 1.5 * transfer_.caps.max_linear_speed_m_s * 1e-4);
  // And no motion at all: the re-anchored set-point asks to stay where the robot was found.
  EXPECT_LT((back_end_.State().X_FM.translation() - pushed).norm(), 1e-6);
}

TEST_F(FollowerRecoveryTest, ANewLeaderSessionReanchorsEvenWithoutAHold) {
  Command(StateCommand::kEnable);
  Run(0.2, true, home_.translation());
  ASSERT_EQ(unit_.state(), OperatingState::kEnabled);
  // A second leader session takes over at once with its own idea of the pose, 5 mm away: the follower keeps its
  // pose (the new session's motion is applied from here), it does not drive 5 mm toward the new set-points.
  session_ = 2;
  const Eigen::Vector3d before = back_end_.State().X_FM.translation();
  Run(0.5, true, home_.translation() + Eigen::Vector3d(0.005, 0, 0));
  EXPECT_LT((back_end_.State().X_FM.translation() - before).norm(), 1e-6);
}

}  // namespace
}  // namespace robossis::teleop
