// The panel's simulated follower, driven in simulated time (Step() without the loop thread, 10 kHz follower ticks):
// the follower unit's states as the panel sees them, a jog played as set-points moving the Bullet RSR by the
// requested amount, refusals leaving it still, the E-stop latching, and a tick that allocates nothing.

#include <gtest/gtest.h>

#include "haptics/transfer/transfer_config.h"
#include "robot/actuation/actuation_config.h"
#include "robot/sim/sim_config.h"
#include "src/core/rt/clock.h"
#include "src/core/config.h"
#include "src/core/units.h"
#include "src/panel/simulated_follower_backend.h"
#include "src/panel/view_model.h"
#include "tests/support/alloc_counter.h"

namespace robossis::panel {
namespace {

using teleop::OperatingState;
using teleop::StateCommand;

class SimulatedFollowerBackendTest : public ::testing::Test {
 protected:
  static teleop::FollowerConfig Follower() {
    const transfer::TransferConfig transfer =
        transfer::TransferConfig::FromYaml(DefaultDataDir() / "config" / "transfer.yaml");
    return teleop::FollowerConfig::FromYaml(DefaultDataDir() / "config" / "follower.yaml", transfer.caps);
  }
  static JogLimits Limits(const teleop::FollowerConfig& follower) {
    JogLimits limits;
    limits.setpoint = follower.setpoint;  // the preview's limits are the follower unit's
    return limits;
  }

  SimulatedFollowerBackendTest()
      : model_(robot::RsrModel::FromYaml(DefaultDataDir() / "config" / "rsr.yaml")),
        follower_(Follower()),
        backend_(model_, sim::LoadSimConfig(DefaultDataDir() / "config" / "sim.yaml", DefaultDataDir()), true,
                 follower_, actuation::ActuationConfig::FromYaml(DefaultDataDir() / "config" / "actuation.yaml"),
                 Limits(follower_), 10000, clock_) {}

  void Run(double seconds) {
    const int ticks = static_cast<int>(seconds * 10000 + 0.5);
    for (int i = 0; i < ticks; ++i) {
      clock_.AdvanceNs(100'000);  // 10 kHz
      backend_.Step();
    }
  }
  teleop::FollowerStatusMessage Status() {
    teleop::FollowerStatusMessage status;
    EXPECT_TRUE(backend_.ReadStatus(status));
    return status;
  }
  void HomeToReady() {
    ASSERT_TRUE(backend_.SendCommand(StateCommand::kHome));
    Run(0.2);
    ASSERT_EQ(Status().state, OperatingState::kReady);
  }
  JogRequest JogZ(double mm, double duration_s) {
    JogRequest request;
    request.axis = JogAxis::kZ;
    request.amount = MmToM(mm);
    request.duration_s = duration_s;
    return request;
  }

  rt::SimulatedClock clock_;
  robot::RsrModel model_;
  teleop::FollowerConfig follower_;
  SimulatedFollowerBackend backend_;
};

TEST_F(SimulatedFollowerBackendTest, StartsDisabledAndRefusesJogsUntilHomed) {
  Run(0.05);
  EXPECT_EQ(Status().state, OperatingState::kDisabled);
  const JogVerdict verdict = backend_.StartJog(JogZ(5, 2));
  EXPECT_FALSE(verdict.accepted);
  EXPECT_NE(verdict.reason.find("disabled"), std::string::npos) << verdict.reason;
  HomeToReady();
}

TEST_F(SimulatedFollowerBackendTest, AJogMovesTheRobotByTheRequestedAmount) {
  HomeToReady();
  const Eigen::Vector3d start = PoseOf(Status()).translation();
  const JogVerdict verdict = backend_.StartJog(JogZ(5, 1));
  ASSERT_TRUE(verdict.accepted) << verdict.reason;
  Run(2.0);
  const Eigen::Vector3d moved = PoseOf(Status()).translation() - start;
  EXPECT_NEAR(MToMm(moved.z()), 5, 0.05);
  EXPECT_NEAR(MToMm(moved.head<2>().norm()), 0, 0.05);
  LoopHealth health;
  ASSERT_TRUE(backend_.ReadHealth(health));
  EXPECT_GE(health.setpoint_age_s, 0);
}

TEST_F(SimulatedFollowerBackendTest, AJogIsPlayedAsSetPointsThatTheFollowerUnitValidatesAndFollows) {
  HomeToReady();
  const std::uint64_t accepted_before = backend_.follower_counters().setpoints_accepted;
  ASSERT_TRUE(backend_.StartJog(JogZ(5, 1)).accepted);
  Run(0.5);
  EXPECT_EQ(Status().state, OperatingState::kEnabled);  // presence + valid set-points: the unit follows
  Run(1.0);
  EXPECT_EQ(Status().state, OperatingState::kReady);  // the move ended: no presence, the unit holds
  const teleop::FollowerCounters& counters = backend_.follower_counters();
  EXPECT_GE(counters.setpoints_accepted - accepted_before, 1400u);  // 1.5 s of 1 kHz set-points
  EXPECT_EQ(counters.setpoints_rejected, 0u);
  EXPECT_EQ(counters.commands_refused, 0u);
  EXPECT_GT(Status().setpoints_accepted, accepted_before);  // the status the panel shows is the unit's
}

TEST_F(SimulatedFollowerBackendTest, ARefusedMoveLeavesTheRobotStill) {
  HomeToReady();
  Run(0.5);
  const Eigen::Vector3d start = PoseOf(Status()).translation();
  const JogVerdict verdict = backend_.StartJog(JogZ(200, 100));
  ASSERT_FALSE(verdict.accepted);
  EXPECT_NE(verdict.reason.find("workspace"), std::string::npos);
  Run(1.0);
  EXPECT_NEAR(MToMm((PoseOf(Status()).translation() - start).norm()), 0, 0.01);
  EXPECT_EQ(Status().state, OperatingState::kReady);
}

TEST_F(SimulatedFollowerBackendTest, EStopLatchesUntilReset) {
  HomeToReady();
  ASSERT_TRUE(backend_.StartJog(JogZ(5, 2)).accepted);
  Run(0.5);
  ASSERT_TRUE(backend_.SendCommand(StateCommand::kEStop));
  Run(0.01);
  EXPECT_EQ(Status().state, OperatingState::kEStop);
  EXPECT_EQ(Status().fault_reason, teleop::FaultReason::kEStop);
  const double z_at_stop = PoseOf(Status()).translation().z();
  // Nothing but a reset leaves it: not enable, not home, not disable; jogs are refused.
  for (StateCommand command : {StateCommand::kEnable, StateCommand::kHome, StateCommand::kDisable}) {
    ASSERT_TRUE(backend_.SendCommand(command));
    Run(0.05);
    EXPECT_EQ(Status().state, OperatingState::kEStop) << teleop::ToString(command);
  }
  EXPECT_FALSE(backend_.StartJog(JogZ(1, 1)).accepted);
  Run(1.0);
  EXPECT_NEAR(MToMm(PoseOf(Status()).translation().z() - z_at_stop), 0, 0.2);  // the rest of the jog never ran
  // The follower unit's reset releases the latch into DISABLED (drives off until the next enable), then Home.
  ASSERT_TRUE(backend_.SendCommand(StateCommand::kReset));
  Run(0.05);
  EXPECT_EQ(Status().state, OperatingState::kDisabled);
  EXPECT_EQ(Status().fault_reason, teleop::FaultReason::kNone);
  HomeToReady();
  // The panel's leader side re-synchronised to where the robot stopped: a new jog runs from there.
  ASSERT_TRUE(backend_.StartJog(JogZ(1, 1)).accepted);
  Run(1.5);
  EXPECT_NEAR(MToMm(PoseOf(Status()).translation().z() - z_at_stop), 1, 0.1);
  EXPECT_EQ(Status().state, OperatingState::kReady);
}

TEST_F(SimulatedFollowerBackendTest, StopEndsAJogWhereItIs) {
  HomeToReady();
  const double z0 = PoseOf(Status()).translation().z();
  ASSERT_TRUE(backend_.StartJog(JogZ(10, 4)).accepted);
  Run(1.0);
  backend_.StopJog();
  Run(1.5);
  const double moved_mm = MToMm(PoseOf(Status()).translation().z() - z0);
  EXPECT_GT(moved_mm, 0.5);
  EXPECT_LT(moved_mm, 5);  // eq. 9 at a quarter of the move: 10 · (1 - cos(pi/4)) / 2 = 1.46 mm
  EXPECT_EQ(Status().state, OperatingState::kReady);
}

TEST_F(SimulatedFollowerBackendTest, HapticModeEnablesAndClutches) {
  HomeToReady();
  HapticModeRequest request;
  request.enabled = true;
  std::string reason;
  ASSERT_TRUE(backend_.RequestHapticMode(request, reason)) << reason;
  Run(0.01);
  EXPECT_EQ(Status().state, OperatingState::kEnabled);
  EXPECT_FALSE(backend_.StartJog(JogZ(1, 1)).accepted);  // the leader owns the robot now
  request.clutched = true;
  ASSERT_TRUE(backend_.RequestHapticMode(request, reason));
  Run(0.01);
  EXPECT_EQ(Status().state, OperatingState::kClutched);
  request = HapticModeRequest{};
  ASSERT_TRUE(backend_.RequestHapticMode(request, reason));
  Run(0.01);
  EXPECT_EQ(Status().state, OperatingState::kReady);
}

TEST_F(SimulatedFollowerBackendTest, TheTickAllocatesNothing) {
  HomeToReady();
  ASSERT_TRUE(backend_.StartJog(JogZ(5, 1)).accepted);
  backend_.SendCommand(StateCommand::kEnable);  // queued before counting: pushing is the panel thread's work
  testing::AllocationCounter counter;
  Run(0.3);  // takes the jog, runs it, takes the command
  EXPECT_EQ(counter.count(), 0u);
}

}  // namespace
}  // namespace robossis::panel
