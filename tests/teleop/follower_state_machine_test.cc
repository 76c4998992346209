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

}  // namespace
}  // namespace robossis::teleop
