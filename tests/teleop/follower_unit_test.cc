#include "src/teleop/follower_unit.h"

#include <cmath>
#include <functional>

#include <gtest/gtest.h>

#include "robot/actuation/pulse_recorder_follower.h"
#include "src/core/config.h"
#include "src/core/units.h"
#include "src/teleop/in_process_link.h"
#include "tests/teleop/follower_fixture.h"
#include "tests/support/alloc_counter.h"
#include "tests/support/forwarding_follower.h"

namespace robossis::teleop {
namespace {

constexpr std::int64_t kTickNs = 100'000;  // 10 kHz

// A follower unit on the simulated clock and the in-process link, with the pulse recorder as its back end, and a
// scripted leader that sends one set-point every 10 ticks (1 kHz).
class FollowerUnitTest : public ::testing::Test, protected ShippedFollowerSetup {
 protected:
  // With the weight the session removes for the Bullet follower: the wrench estimate's longest path runs each tick
  // (TickAllocatesNothing covers it).
  static FollowerConfig WithWeightRemoved(FollowerConfig c) {
    c.wrench.carried_mass_kg = 2.5;
    c.wrench.gravity_F_mps2 = Eigen::Vector3d(0, -9.81, 0);
    c.wrench.remove_arm_weight = true;
    return c;
  }
  const FollowerConfig config_ = WithWeightRemoved(ShippedFollowerConfig());
  rt::SimulatedClock clock_;
  InProcessLink link_{clock_};
  actuation::PulseRecorderFollower back_end_{model_, actuation_, home_, 1 << 16, 1 << 16};
  FollowerUnit unit_{model_, actuation_, config_, back_end_, link_, clock_};

  // The leader's script: position offset from home and its velocity at time t.
  Eigen::Vector3d leader_offset_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d leader_velocity_ = Eigen::Vector3d(0.005, 0, 0);  // 5 mm/s along x
  std::uint8_t leader_flags_ = kSetPointPresence;
  bool leader_sending_ = true;
  std::uint64_t sequence_ = 0;
  std::int64_t tick_ = 0;

  void Command(StateCommand c) {
    StateCommandMessage m;
    m.command = c;
    ASSERT_TRUE(link_.operator_commands().Send(m));
  }

  void SendSetPoint() {
    const Eigen::Vector3d p = home_.translation() + leader_offset_;
    SetPointMessage m;
    m.sequence = ++sequence_;
    m.leader_session = 1;
    m.stamp_ns = clock_.now_ns();
    m.p_FM = {p.x(), p.y(), p.z()};
    m.twist_F = {leader_velocity_.x(), leader_velocity_.y(), leader_velocity_.z(), 0, 0, 0};
    m.flags = leader_flags_;
    link_.SendSetPoint(m);
  }

  // One 10 kHz tick: every 10th the leader moves and sends, then the follower ticks.
  void Step() {
    clock_.AdvanceNs(kTickNs);
    ++tick_;
    if (tick_ % 10 == 0) {
      leader_offset_ += 1e-3 * leader_velocity_;
      if (leader_sending_) SendSetPoint();
    }
    unit_.Tick();
  }
  void Run(double seconds) {
    const auto n = static_cast<std::int64_t>(std::llround(seconds * 1e4));
    for (std::int64_t i = 0; i < n; ++i) Step();
  }
  double CmdX() const { return unit_.commanded_pose().translation().x() - home_.translation().x(); }
  // Caps above what the motors' step rate can do along z (100 mm/s), with the acceleration to reach them.
  FollowerConfig AboveTheStepRate() const {
    FollowerConfig fast = config_;
    fast.setpoint.caps.max_linear_speed_m_s = 0.1;
    fast.setpoint.max_linear_accel_m_s2 = 100;
    return fast;
  }
  void EnableAndFollow() {
    Command(StateCommand::kEnable);
    Run(0.05);
    ASSERT_EQ(unit_.state(), OperatingState::kEnabled);
  }
};

TEST_F(FollowerUnitTest, FollowsTheSetPointsOnceEnabled) {
  EnableAndFollow();
  const double x0 = CmdX();
  Run(1.0);
  EXPECT_NEAR(CmdX() - x0, 0.005, 2e-4);  // 5 mm/s for 1 s
  EXPECT_EQ(unit_.counters().setpoints_rejected, 0u);
  EXPECT_EQ(unit_.counters().limit_violations, 0u);
  EXPECT_GT(back_end_.events().size(), 0u);  // the pulse recorder recorded the steps of the motion
}

TEST_F(FollowerUnitTest, PoweringUpAgainStartsFromWhereTheMotorsAre) {
  // Caps above what the step rate can do (100 mm/s along z): the motors lag the commanded pose. After a disable,
  // the next enable must start from the motors' pose, not catch up with the old command in one burst of steps.
  InProcessLink link(clock_);
  actuation::PulseRecorderFollower back_end(model_, actuation_, home_, 1 << 20, 1 << 20);
  FollowerUnit unit(model_, actuation_, AboveTheStepRate(), back_end, link, clock_);
  std::uint64_t seq = 0;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  const auto run = [&](double seconds, const Eigen::Vector3d& velocity, double* max_jump) {
    for (int i = 0; i < static_cast<int>(std::llround(seconds * 1e4)); ++i) {
      clock_.AdvanceNs(kTickNs);
      if (i % 10 == 0) {
        offset += 1e-3 * velocity;
        const Eigen::Vector3d p = home_.translation() + offset;
        SetPointMessage m;
        m.sequence = ++seq;
        m.leader_session = 1;
        m.stamp_ns = clock_.now_ns();
        m.p_FM = {p.x(), p.y(), p.z()};
        m.twist_F = {velocity.x(), velocity.y(), velocity.z(), 0, 0, 0};
        m.flags = kSetPointPresence;
        link.SendSetPoint(m);
      }
      const Eigen::Vector3d before = back_end.State().X_FM.translation();
      unit.Tick();
      if (max_jump) *max_jump = std::max(*max_jump, (back_end.State().X_FM.translation() - before).norm());
    }
  };
  StateCommandMessage c;
  c.command = StateCommand::kEnable;
  ASSERT_TRUE(link.operator_commands().Send(c));
  run(0.3, Eigen::Vector3d(0, 0, 0.1), nullptr);
  ASSERT_EQ(unit.state(), OperatingState::kEnabled);
  c.command = StateCommand::kDisable;
  ASSERT_TRUE(link.operator_commands().Send(c));
  run(0.2, Eigen::Vector3d::Zero(), nullptr);
  EXPECT_LT((unit.commanded_pose().translation() - back_end.State().X_FM.translation()).norm(), 1e-6);
  c.command = StateCommand::kEnable;
  ASSERT_TRUE(link.operator_commands().Send(c));
  double max_jump = 0;
  run(0.3, Eigen::Vector3d::Zero(), &max_jump);
  EXPECT_EQ(unit.state(), OperatingState::kEnabled);
  // At most one tick at the cap (10 um at 100 mm/s), with room for the motors' step quantisation.
  EXPECT_LE(max_jump, 0.1 * 1e-4 * 1.5);
}

TEST_F(FollowerUnitTest, CommandsOnlyWhatTheMotorsAchieve) {
  // Caps above what the step rate can do (100 mm/s along z): the actuator shortens the joint steps, and the
  // commanded pose must stay with the motors instead of running ahead of them (and catching up later at the full
  // step rate, e.g. after a hold).
  InProcessLink link(clock_);
  actuation::PulseRecorderFollower back_end(model_, actuation_, home_, 1 << 20, 1 << 20);
  FollowerUnit unit(model_, actuation_, AboveTheStepRate(), back_end, link, clock_);
  StateCommandMessage c;
  c.command = StateCommand::kEnable;
  ASSERT_TRUE(link.operator_commands().Send(c));
  double worst_gap = 0;
  std::uint64_t seq = 0;
  ::robossis::testing::AllocationCounter counter;  // the forward kinematics of the shortened steps included
  for (int i = 0; i < 3000; ++i) {
    clock_.AdvanceNs(kTickNs);
    if (i % 10 == 0) {
      const Eigen::Vector3d p = home_.translation() + Eigen::Vector3d(0, 0, 1e-4 * (i / 10));
      SetPointMessage m;
      m.sequence = ++seq;
      m.leader_session = 1;
      m.stamp_ns = clock_.now_ns();
      m.p_FM = {p.x(), p.y(), p.z()};
      m.twist_F = {0, 0, 0.1, 0, 0, 0};
      m.flags = kSetPointPresence;
      link.SendSetPoint(m);
    }
    unit.Tick();
    worst_gap = std::max(worst_gap,
                         (unit.commanded_pose().translation() - back_end.State().X_FM.translation()).norm());
  }
  EXPECT_EQ(counter.count(), 0u);
  ASSERT_EQ(unit.state(), OperatingState::kEnabled);
  EXPECT_GT(unit.commanded_pose().translation().z() - home_.translation().z(), 5e-3);  // it did move
  // The motors' step quantisation (a few micrometres), not millimetres of lag.
  EXPECT_LT(worst_gap, 20e-6);
}

TEST_F(FollowerUnitTest, AStalledTickLagsInsteadOfJumping) {
  EnableAndFollow();
  Run(0.2);
  // The loop stalls for 14 ms (as on a loaded machine) while the leader keeps moving; the next tick commands at
  // most max_tick_interval_s of motion at the caps, not the 14 ms the caps would allow.
  const double before = CmdX();
  clock_.AdvanceNs(140 * kTickNs);
  leader_offset_ += 0.014 * leader_velocity_;
  SendSetPoint();
  unit_.Tick();
  const double cap_step = transfer_.caps.max_linear_speed_m_s * config_.watchdog.max_tick_interval_s;
  EXPECT_LE(CmdX() - before, cap_step * 1.0001);
  EXPECT_GT(CmdX() - before, 0.0);  // it still moves towards the set-point
  EXPECT_EQ(unit_.state(), OperatingState::kEnabled);
}

TEST_F(FollowerUnitTest, NoMotionWithoutPresence) {
  leader_flags_ = 0;
  Command(StateCommand::kEnable);
  Run(0.5);
  EXPECT_EQ(unit_.state(), OperatingState::kReady);
  EXPECT_EQ(CmdX(), 0.0);
  leader_flags_ = kSetPointPresence;
  Run(0.5);
  EXPECT_EQ(unit_.state(), OperatingState::kEnabled);
  EXPECT_GT(CmdX(), 0.001);
}

TEST_F(FollowerUnitTest, WatchdogHoldsWithin30MsOfTheLastSetPoint) {
  EnableAndFollow();
  Run(0.5);
  leader_sending_ = false;
  const double t_last = clock_.NowS() - 1e-4 * (tick_ % 10);  // the last set-point's arrival
  bool held = false;
  double t_hold = 0;
  for (int i = 0; i < 1000 && !held; ++i) {
    Step();
    if (unit_.state() != OperatingState::kEnabled) {
      held = true;
      t_hold = clock_.NowS();
    }
  }
  ASSERT_TRUE(held);
  EXPECT_LE(t_hold - t_last, config_.watchdog.hold_after_s + 1.5e-4);
  EXPECT_EQ(unit_.counters().watchdog_holds, 1u);
  // Held: it never speeds up again, never passes the last set-point by more than its extrapolation, and stands
  // still.
  const double x_last = leader_offset_.x();
  double prev_x = CmdX(), prev_v = 1e300;
  for (int i = 0; i < 3000; ++i) {
    Step();
    const double v = (CmdX() - prev_x) / 1e-4;
    EXPECT_LE(v, std::min(prev_v, transfer_.caps.max_linear_speed_m_s) + 1e-9);
    EXPECT_LE(CmdX(), x_last + 0.005 * config_.watchdog.max_extrapolation_s + 1e-9);
    prev_v = v;
    prev_x = CmdX();
  }
  EXPECT_NEAR(prev_v, 0.0, 1e-12);
}

TEST_F(FollowerUnitTest, LeaderLostDisablesTheDrives) {
  EnableAndFollow();
  leader_sending_ = false;
  Run(config_.watchdog.leader_lost_after_s + 0.01);
  EXPECT_EQ(unit_.state(), OperatingState::kDisabled);
  EXPECT_EQ(unit_.reason(), FaultReason::kLeaderLost);
  EXPECT_EQ(unit_.counters().leader_lost, 1u);
  EXPECT_FALSE(back_end_.State().enabled);
}

TEST_F(FollowerUnitTest, EStopLatchesUntilResetAndResumesWithoutAJump) {
  EnableAndFollow();
  Run(0.2);
  Command(StateCommand::kEStop);
  Step();
  EXPECT_EQ(unit_.state(), OperatingState::kEStop);
  const double x_stop = CmdX();
  Run(0.5);  // set-points keep coming: nothing moves
  EXPECT_EQ(unit_.state(), OperatingState::kEStop);
  EXPECT_EQ(CmdX(), x_stop);
  Command(StateCommand::kEnable);  // refused while latched
  Run(0.01);
  EXPECT_EQ(unit_.state(), OperatingState::kEStop);
  Command(StateCommand::kReset);
  Command(StateCommand::kEnable);
  double prev = CmdX();
  for (int i = 0; i < 2000; ++i) {
    Step();
    EXPECT_LE(std::abs(CmdX() - prev), 1.02 * transfer_.caps.max_linear_speed_m_s * 1e-4 + 1e-12) << i;
    prev = CmdX();
  }
  EXPECT_EQ(unit_.state(), OperatingState::kEnabled);
  EXPECT_NEAR(CmdX() - x_stop, 0.005 * 0.2, 2e-4);  // re-anchored: continues from where it stopped
}

TEST_F(FollowerUnitTest, ClutchReanchorsWithoutAJump) {
  EnableAndFollow();
  Run(0.2);
  leader_flags_ = kSetPointPresence | kSetPointClutched;
  Run(0.01);
  EXPECT_EQ(unit_.state(), OperatingState::kClutched);
  const double x_clutch = CmdX();
  Run(1.0);  // the hand moves 5 mm with the clutch open
  leader_flags_ = kSetPointPresence;
  double prev = CmdX();
  for (int i = 0; i < 1000; ++i) {
    Step();
    EXPECT_LE(std::abs(CmdX() - prev), 1.02 * transfer_.caps.max_linear_speed_m_s * 1e-4 + 1e-12) << i;
    prev = CmdX();
  }
  EXPECT_LT(CmdX() - x_clutch, 0.002);  // did not catch up the 5 mm moved while clutched
}

// 10 000 commands flood a producer's queue (64 taken, the rest dropped and counted), then the E-stop comes from
// `send`; the drives must be off after the first tick that follows it (ticks counted on the simulated clock).
class FollowerEStopTest : public FollowerUnitTest {
 protected:
  void FloodThenEStopDisablesTheDrivesInOneTick(bool leader_queue, const std::function<void()>& send) {
    EnableAndFollow();
    ASSERT_TRUE(back_end_.State().enabled);
    StateCommandMessage enable;
    enable.command = StateCommand::kEnable;  // idempotent once enabled: the flood itself changes nothing
    int refused = 0;
    for (int i = 0; i < 10000; ++i) {
      const bool ok = leader_queue ? link_.SendCommand(enable) : link_.operator_commands().Send(enable);
      if (!ok) ++refused;
    }
    ASSERT_EQ(refused, 10000 - 64);  // the queue is full
    ASSERT_EQ(link_.commands_dropped(), 10000u - 64u);
    send();
    int ticks = 0;
    while (back_end_.State().enabled && ticks < 1000) {
      Step();
      ++ticks;
    }
    EXPECT_EQ(ticks, 1);  // the drives were off after the first tick following the E-stop
    EXPECT_EQ(unit_.state(), OperatingState::kEStop);
    EXPECT_EQ(unit_.reason(), FaultReason::kEStop);
    EXPECT_EQ(unit_.counters().estops, 1u);
    // Latched: the queued enables and the set-points leave it alone; only a reset does.
    Run(0.05);
    EXPECT_EQ(unit_.state(), OperatingState::kEStop);
    EXPECT_FALSE(back_end_.State().enabled);
    Command(StateCommand::kReset);
    Step();
    EXPECT_EQ(unit_.state(), OperatingState::kDisabled);
  }
};

TEST_F(FollowerEStopTest, TheOperatorsEStopCommandBehindAFullQueue) {
  FloodThenEStopDisablesTheDrivesInOneTick(false, [&] {
    StateCommandMessage estop;
    estop.command = StateCommand::kEStop;
    EXPECT_TRUE(link_.operator_commands().Send(estop));  // the old command, routed to the level: never refused
  });
}

TEST_F(FollowerEStopTest, TheLeadersEStopBehindAFullQueue) {
  FloodThenEStopDisablesTheDrivesInOneTick(true, [&] { link_.SendEStop(); });
}

TEST_F(FollowerEStopTest, AnEStopFromAnotherThreadWhileTheLeaderFloods) {
  // The operator's port engages the level while the leader's queue is full: any producer may E-stop.
  FloodThenEStopDisablesTheDrivesInOneTick(true, [&] { link_.operator_commands().SendEStop(); });
}

TEST_F(FollowerEStopTest, AResetTakenInTheTickOfAnEStopDoesNotReleaseIt) {
  EnableAndFollow();
  // A reset queued, then an E-stop: the level overtakes the queue, so the reset (which may have been sent before
  // the E-stop) must not release it in the same tick.
  Command(StateCommand::kReset);
  link_.SendEStop();
  Step();
  EXPECT_EQ(unit_.state(), OperatingState::kEStop);
  EXPECT_FALSE(back_end_.State().enabled);
  Command(StateCommand::kReset);  // a later reset does
  Step();
  EXPECT_EQ(unit_.state(), OperatingState::kDisabled);
}

TEST_F(FollowerEStopTest, TwoEStopsBetweenTwoTicksAndOneAfterAResetEachAct) {
  EnableAndFollow();
  link_.SendEStop();
  link_.SendEStop();
  Step();
  EXPECT_EQ(unit_.state(), OperatingState::kEStop);
  Command(StateCommand::kReset);
  Step();
  ASSERT_EQ(unit_.state(), OperatingState::kDisabled);
  EnableAndFollow();
  link_.SendEStop();  // the count grew again: a second E-stop is not merged into the first
  Step();
  EXPECT_EQ(unit_.state(), OperatingState::kEStop);
  EXPECT_EQ(unit_.counters().estops, 2u);
}

TEST_F(FollowerUnitTest, BackEndFaultLatchesAndResets) {
  EnableAndFollow();
  back_end_.InjectFault(robot::FollowerFault::kExternal);
  Step();
  EXPECT_EQ(unit_.state(), OperatingState::kFault);
  EXPECT_EQ(unit_.reason(), FaultReason::kBackEnd);
  back_end_.InjectFault(robot::FollowerFault::kNone);
  Run(0.05);
  EXPECT_EQ(unit_.state(), OperatingState::kFault);
  Command(StateCommand::kReset);
  Command(StateCommand::kEnable);
  Run(0.05);
  EXPECT_EQ(unit_.state(), OperatingState::kEnabled);
}

TEST_F(FollowerUnitTest, RejectsBadSetPointsAndCountsThemByReason) {
  EnableAndFollow();
  leader_offset_.z() = 0.2;  // far outside: every set-point infeasible
  Run(0.1);
  EXPECT_GT(unit_.counters().setpoints_by_verdict[static_cast<int>(SetPointVerdict::kInfeasible)], 50u);
  EXPECT_NE(unit_.state(), OperatingState::kEnabled);  // the watchdog held: no valid set-point
  EXPECT_EQ(unit_.counters().limit_violations, 0u);
}

TEST_F(FollowerUnitTest, DrivenIntoTheStrokeLimitsItStaysInside) {
  // The leader keeps going up at 9 mm/s for 9 s (81 mm, past the upper strokes): the set-points past the limit
  // are rejected, the guard stops the commanded pose at the wall, and the measured joints never break a limit.
  EnableAndFollow();
  leader_velocity_ = Eigen::Vector3d(0, 0, 0.009);  // within the cap, towards the upper strokes
  Run(9.0);
  EXPECT_EQ(unit_.counters().limit_violations, 0u);
  EXPECT_GT(unit_.counters().setpoints_accepted, 1000u);
  EXPECT_TRUE(robot::CalcInverseKinematics(model_, unit_.commanded_pose()).feasible);
}

TEST_F(FollowerUnitTest, AHandFarFasterThanTheCapsNeverDrivesTheRobotFaster) {
  // 250 mm/s (25x the cap), as a surgeon's hand can move: the set-points are refused as too fast, the watchdog
  // holds, and the commanded pose never moves faster than the cap.
  EnableAndFollow();
  leader_velocity_ = Eigen::Vector3d(0.25, 0, 0);
  double prev = CmdX();
  for (int i = 0; i < 5000; ++i) {
    Step();
    EXPECT_LE(std::abs(CmdX() - prev), 1.02 * transfer_.caps.max_linear_speed_m_s * 1e-4 + 1e-12) << i;
    prev = CmdX();
  }
  EXPECT_GT(unit_.counters().setpoints_by_verdict[static_cast<int>(SetPointVerdict::kTooFast)], 100u);
  EXPECT_EQ(unit_.counters().limit_violations, 0u);
  EXPECT_TRUE(robot::CalcInverseKinematics(model_, unit_.commanded_pose()).feasible);
}

TEST_F(FollowerUnitTest, PublishesStatusAndRecordsEveryTick) {
  EnableAndFollow();
  FollowerTickRecord r;
  int n = 0;
  while (unit_.TakeRecord(r)) ++n;
  EXPECT_EQ(n, 500);
  EXPECT_EQ(r.state, OperatingState::kEnabled);
  FollowerStatusMessage s;
  ASSERT_TRUE(link_.TakeFollowerStatus(s));
  EXPECT_EQ(s.state, OperatingState::kEnabled);
  EXPECT_GE(unit_.counters().status_published, 49u);  // 1 kHz over 50 ms
}

TEST_F(FollowerUnitTest, RecordsTheStampOfTheSetPointItUsedAndWhenItCommanded) {
  // The latency's two instants: the device-sample stamp of the newest valid set-point, and the command time.
  EnableAndFollow();
  FollowerTickRecord r;
  while (unit_.TakeRecord(r)) {
  }
  Run(0.0105);  // ten leader periods and half a tick-period more
  int accepted = 0;
  while (unit_.TakeRecord(r)) {
    if (r.took_setpoint && r.setpoint_verdict == SetPointVerdict::kAccepted) {
      ++accepted;
      EXPECT_EQ(r.setpoint_stamp_ns, std::llround(r.time_s * 1e9));  // sent this very tick (the script's leader)
    }
    EXPECT_GE(r.setpoint_stamp_ns, 0);
    EXPECT_LE(1e-9 * static_cast<double>(r.setpoint_stamp_ns), r.time_s);
    EXPECT_EQ(r.command_time_s, r.time_s);  // the simulated clock stands still within a tick
  }
  EXPECT_EQ(accepted, 10);
}

// A back end that knows the true external wrench, as a simulation does: the pulse recorder's measurement with a
// wrench of its own for each Service() (the n-th: TrueWrench(n)).
class KnownLoadFollower final : public ::robossis::testing::ForwardingFollower {
 public:
  using ForwardingFollower::ForwardingFollower;
  static Vector6d TrueWrench(std::uint64_t n) {
    Vector6d W;
    W << 0.5 * static_cast<double>(n), -120, 300, 2, -7, 0.25 * static_cast<double>(n);
    return W;
  }
  void Service(double now_s) noexcept override {
    inner_.Service(now_s);
    ++services_;
  }
  robot::RsrFollowerState State() const noexcept override {
    robot::RsrFollowerState s = inner_.State();
    s.true_wrench_known = true;
    s.true_wrench_F = TrueWrench(services_);
    return s;
  }

 private:
  std::uint64_t services_ = 0;
};

// The records carry the true external wrench of the measurement the tick took, as the back end reported it, and
// say it is unknown where the back end does not know it (hardware; here the pulse recorder).
TEST_F(FollowerUnitTest, RecordsCarryTheBackEndsTrueWrenchOnlyWhereItKnowsIt) {
  EnableAndFollow();
  FollowerTickRecord r;
  int records = 0;
  while (unit_.TakeRecord(r)) {
    ++records;
    EXPECT_FALSE(r.true_load_known);
  }
  EXPECT_EQ(records, 500);

  InProcessLink link(clock_);
  actuation::PulseRecorderFollower recorder(model_, actuation_, home_, 1 << 16, 1 << 16);
  KnownLoadFollower back_end(recorder);
  FollowerUnit unit(model_, actuation_, config_, back_end, link, clock_);
  for (int i = 0; i < 20; ++i) {
    clock_.AdvanceNs(kTickNs);
    unit.Tick();
  }
  records = 0;
  while (unit.TakeRecord(r)) {
    ++records;
    ASSERT_TRUE(r.true_load_known);
    const Vector6d W = KnownLoadFollower::TrueWrench(r.tick);  // one Service() a tick
    for (int i = 0; i < 6; ++i) EXPECT_EQ(r.true_wrench_F[i], W[i]) << "tick " << r.tick << ", component " << i;
  }
  EXPECT_EQ(records, 20);
}

TEST_F(FollowerUnitTest, TickAllocatesNothing) {
  leader_flags_ = kSetPointPresence | kSetPointEnergyBudget;  // the network form's follower half runs too
  Command(StateCommand::kEnable);
  Run(0.01);
  leader_offset_.z() = 0.069;  // near the upper strokes: the guard works too
  leader_velocity_ = Eigen::Vector3d(0.002, 0, 0.002);
  Run(0.01);
  testing::AllocationCounter counter;
  Run(0.5);
  leader_sending_ = false;
  Run(0.1);  // the watchdog's hold as well
  EXPECT_EQ(counter.count(), 0u);
}

}  // namespace
}  // namespace robossis::teleop
