#include "src/teleop/follower_state_machine.h"

#include <gtest/gtest.h>

#include "robot/actuation/actuation_config.h"
#include "robot/actuation/pulse_recorder_follower.h"
#include "robot/rsr_model.h"
#include "src/core/config.h"

namespace robossis::teleop {
namespace {

class FollowerStateMachineTest : public ::testing::Test {
 protected:
  const robot::RsrModel model_ = robot::RsrModel::Default();
  const actuation::ActuationConfig actuation_ = actuation::ActuationConfig::FromYaml(DefaultDataDir() / "config" / "actuation.yaml");
  actuation::PulseRecorderFollower back_end_{model_, actuation_, model_.geometry().X_FM_home, 16, 16};
  FollowerStateMachine sm_;
  FollowerInputs live_{.presence = true, .clutched = false, .have_valid_setpoint = true, .leader_lost = false};

  void EnableAndFollow() {
    ASSERT_TRUE(sm_.OnCommand(StateCommand::kEnable, back_end_));
    ASSERT_EQ(sm_.state(), OperatingState::kReady);
    sm_.Update(live_, back_end_);
    ASSERT_EQ(sm_.state(), OperatingState::kEnabled);
  }
};

TEST_F(FollowerStateMachineTest, StartsDisabledAndEnablesThroughReady) {
  EXPECT_EQ(sm_.state(), OperatingState::kDisabled);
  EnableAndFollow();
  EXPECT_TRUE(back_end_.State().enabled);
}

TEST_F(FollowerStateMachineTest, NoMotionWithoutPresence) {
  EnableAndFollow();
  FollowerInputs absent = live_;
  absent.presence = false;
  sm_.Update(absent, back_end_);
  EXPECT_EQ(sm_.state(), OperatingState::kReady);
  EXPECT_FALSE(sm_.following());
  sm_.Update(live_, back_end_);
  EXPECT_TRUE(sm_.following());
}

TEST_F(FollowerStateMachineTest, ClutchHoldsAndReleases) {
  EnableAndFollow();
  FollowerInputs clutched = live_;
  clutched.clutched = true;
  sm_.Update(clutched, back_end_);
  EXPECT_EQ(sm_.state(), OperatingState::kClutched);
  EXPECT_FALSE(sm_.following());
  sm_.Update(live_, back_end_);
  EXPECT_EQ(sm_.state(), OperatingState::kEnabled);
}

TEST_F(FollowerStateMachineTest, EStopLatchesUntilReset) {
  EnableAndFollow();
  EXPECT_TRUE(sm_.OnCommand(StateCommand::kEStop, back_end_));
  EXPECT_EQ(sm_.state(), OperatingState::kEStop);
  EXPECT_FALSE(back_end_.State().enabled);
  for (int i = 0; i < 10; ++i) sm_.Update(live_, back_end_);
  EXPECT_EQ(sm_.state(), OperatingState::kEStop);
  EXPECT_FALSE(sm_.OnCommand(StateCommand::kEnable, back_end_));
  EXPECT_FALSE(sm_.OnCommand(StateCommand::kDisable, back_end_));
  EXPECT_EQ(sm_.state(), OperatingState::kEStop);
  EXPECT_EQ(sm_.reason(), FaultReason::kEStop);
  EXPECT_TRUE(sm_.OnCommand(StateCommand::kReset, back_end_));
  EXPECT_EQ(sm_.state(), OperatingState::kDisabled);  // a reset does not re-enable by itself
  EnableAndFollow();
}

TEST_F(FollowerStateMachineTest, BackEndFaultLatchesWithItsReasonUntilItsCauseIsGone) {
  EnableAndFollow();
  back_end_.InjectFault(robot::FollowerFault::kDrive);
  sm_.Update(live_, back_end_);
  EXPECT_EQ(sm_.state(), OperatingState::kFault);
  EXPECT_EQ(sm_.reason(), FaultReason::kBackEnd);
  EXPECT_EQ(sm_.back_end_fault(), robot::FollowerFault::kDrive);
  EXPECT_FALSE(sm_.OnCommand(StateCommand::kReset, back_end_));  // the fault input is still raised
  EXPECT_EQ(sm_.state(), OperatingState::kFault);
  back_end_.InjectFault(robot::FollowerFault::kNone);
  sm_.Update(live_, back_end_);
  EXPECT_EQ(sm_.state(), OperatingState::kFault);  // latched: the cause going away is not a reset
  EXPECT_TRUE(sm_.OnCommand(StateCommand::kReset, back_end_));
  EXPECT_EQ(sm_.state(), OperatingState::kDisabled);
  EnableAndFollow();
}

TEST_F(FollowerStateMachineTest, LeaderLostDisablesTheDrives) {
  EnableAndFollow();
  FollowerInputs lost = live_;
  lost.have_valid_setpoint = false;
  lost.leader_lost = true;
  sm_.Update(lost, back_end_);
  EXPECT_EQ(sm_.state(), OperatingState::kDisabled);
  EXPECT_EQ(sm_.reason(), FaultReason::kLeaderLost);
  EXPECT_FALSE(back_end_.State().enabled);
}

// An open-loop back end (step/direction drives): unhomed at its start, homed only by Home(), which it refuses until
// its feedback is alive; it counts the calls.
class OpenLoopFollower final : public robot::Follower {
 public:
  bool Enable() noexcept override {
    if (!state_.homed) return false;
    return state_.enabled = true;
  }
  void Disable() noexcept override { state_.enabled = false; }
  bool Home() noexcept override {
    ++home_calls;
    if (!feedback_alive || state_.enabled) return false;
    return state_.homed = true;
  }
  bool MeasuresJoints() const noexcept override { return false; }
  bool ResetFault() noexcept override { return true; }
  void Command(const robot::RsrJointCommand&) noexcept override {}
  void Service(double) noexcept override {}
  robot::RsrFollowerState State() const noexcept override { return state_; }

  bool feedback_alive = true;
  int home_calls = 0;

 private:
  robot::RsrFollowerState state_;
};

class FollowerStateMachineHomingTest : public ::testing::Test {
 protected:
  OpenLoopFollower back_end_;
  FollowerStateMachine sm_;
  FollowerInputs live_{.presence = true, .clutched = false, .have_valid_setpoint = true, .leader_lost = false};
};

TEST_F(FollowerStateMachineHomingTest, EnableWhileUnhomedIsRefusedWithItsReasonAndNeverHomes) {
  EXPECT_FALSE(sm_.OnCommand(StateCommand::kEnable, back_end_));
  EXPECT_EQ(sm_.state(), OperatingState::kDisabled);
  EXPECT_EQ(sm_.reason(), FaultReason::kNotHomed);
  for (int i = 0; i < 10; ++i) sm_.Update(live_, back_end_);
  EXPECT_EQ(sm_.state(), OperatingState::kDisabled);
  EXPECT_EQ(sm_.reason(), FaultReason::kNotHomed);
  EXPECT_EQ(back_end_.home_calls, 0);
  EXPECT_FALSE(back_end_.State().homed);
  EXPECT_FALSE(back_end_.State().enabled);
  EXPECT_EQ(sm_.transitions(), 0u);
}

TEST_F(FollowerStateMachineHomingTest, HomeIsExplicitAndLeavesTheDrivesOff) {
  ASSERT_FALSE(sm_.OnCommand(StateCommand::kEnable, back_end_));
  EXPECT_TRUE(sm_.OnCommand(StateCommand::kHome, back_end_));
  EXPECT_EQ(back_end_.home_calls, 1);
  EXPECT_TRUE(back_end_.State().homed);
  sm_.Update(live_, back_end_);
  EXPECT_EQ(sm_.state(), OperatingState::kDisabled);  // homed, not enabled
  EXPECT_EQ(sm_.reason(), FaultReason::kNone);        // the refusal's reason is gone once homed
  EXPECT_FALSE(back_end_.State().enabled);
  EXPECT_TRUE(sm_.OnCommand(StateCommand::kEnable, back_end_));
  EXPECT_EQ(sm_.state(), OperatingState::kReady);
  sm_.Update(live_, back_end_);
  EXPECT_EQ(sm_.state(), OperatingState::kEnabled);
  EXPECT_FALSE(sm_.OnCommand(StateCommand::kHome, back_end_));  // not while powered
  EXPECT_EQ(sm_.state(), OperatingState::kEnabled);
  EXPECT_EQ(back_end_.home_calls, 1);
}

TEST_F(FollowerStateMachineHomingTest, HomeWaitsForTheBackEndAndAnEnableMeanwhileFollowsIt) {
  back_end_.feedback_alive = false;
  ASSERT_TRUE(sm_.OnCommand(StateCommand::kHome, back_end_));
  EXPECT_EQ(sm_.state(), OperatingState::kHoming);
  EXPECT_TRUE(sm_.OnCommand(StateCommand::kEnable, back_end_));  // home, then enable: kept until homed
  sm_.Update(live_, back_end_);
  EXPECT_EQ(sm_.state(), OperatingState::kHoming);
  EXPECT_FALSE(back_end_.State().enabled);
  back_end_.feedback_alive = true;
  sm_.Update(live_, back_end_);
  EXPECT_EQ(sm_.state(), OperatingState::kReady);
  EXPECT_TRUE(back_end_.State().enabled);
}

TEST_F(FollowerStateMachineHomingTest, ADisableDuringHomingDropsThePendingEnable) {
  back_end_.feedback_alive = false;
  ASSERT_TRUE(sm_.OnCommand(StateCommand::kHome, back_end_));
  ASSERT_TRUE(sm_.OnCommand(StateCommand::kEnable, back_end_));
  ASSERT_TRUE(sm_.OnCommand(StateCommand::kDisable, back_end_));
  back_end_.feedback_alive = true;
  sm_.Update(live_, back_end_);
  EXPECT_EQ(sm_.state(), OperatingState::kDisabled);
  EXPECT_FALSE(back_end_.State().homed);  // the homing was cancelled with it
  EXPECT_FALSE(back_end_.State().enabled);
}

TEST_F(FollowerStateMachineHomingTest, HomeIsRefusedWhileLatched) {
  ASSERT_TRUE(sm_.OnCommand(StateCommand::kEStop, back_end_));
  EXPECT_FALSE(sm_.OnCommand(StateCommand::kHome, back_end_));
  EXPECT_EQ(sm_.state(), OperatingState::kEStop);
  EXPECT_EQ(back_end_.home_calls, 0);
}

}  // namespace
}  // namespace robossis::teleop
