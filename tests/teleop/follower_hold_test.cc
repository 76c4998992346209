// The follower's hold: from the speed cap, the commanded motion decelerates to rest within the acceleration cap
// (the validator's), reaches the hold state within the watchdog's 30 ms, and never crosses a joint limit; a failed
// flight recorder holds it the same way.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "robot/actuation/pulse_recorder_follower.h"
#include "src/core/config.h"
#include "src/teleop/follower_unit.h"
#include "src/teleop/in_process_link.h"
#include "tests/teleop/follower_fixture.h"

namespace robossis::teleop {
namespace {

constexpr std::int64_t kTickNs = 100'000;  // 10 kHz
constexpr double kTickS = 1e-4;

// A follower unit on the simulated clock with the pulse recorder, and a 1 kHz leader that ramps its velocity up
// to the speed cap along `direction_` within the acceleration cap (so that the validator accepts every set-point),
// then cruises. The acceleration cap is the test's parameter: the shipped one (the stop takes 2 ms) and a low one
// (0.1 m/s^2: the stop takes 0.1 s, longer than the watchdog's 30 ms, so the hold itself decelerates).
class FollowerHoldTest : public ::testing::TestWithParam<double>, protected ShippedFollowerSetup {
 protected:
  FollowerConfig config_ = Config(GetParam());
  const double v_cap_ = config_.setpoint.caps.max_linear_speed_m_s;
  const double a_cap_ = config_.setpoint.max_linear_accel_m_s2;
  rt::SimulatedClock clock_;
  InProcessLink link_{clock_};
  actuation::PulseRecorderFollower back_end_{model_, actuation_, home_, 1 << 16, 1 << 16};
  FollowerUnit unit_{model_, actuation_, config_, back_end_, link_, clock_};

  Eigen::Vector3d direction_ = Eigen::Vector3d::UnitX();
  double leader_s_ = 0, leader_v_ = 0;  // the leader's distance along direction_ and its speed
  // Rotation instead (rotating_): the leader turns about axis_ (in F), ramping to the angular cap.
  bool rotating_ = false;
  Eigen::Vector3d axis_ = Eigen::Vector3d::UnitZ();
  double leader_angle_ = 0, leader_w_ = 0;
  const double w_cap_ = config_.setpoint.caps.max_angular_speed_rad_s;
  const double alpha_cap_ = config_.setpoint.max_angular_accel_rad_s2;
  std::uint8_t leader_flags_ = kSetPointPresence;
  bool leader_sending_ = true;
  std::uint64_t sequence_ = 0;
  std::int64_t tick_ = 0;
  double last_arrival_s_ = 0;
  // The commanded position's history, for the finite-difference velocity and acceleration.
  Eigen::Vector3d prev_p_ = Eigen::Vector3d::Zero(), prev_v_ = Eigen::Vector3d::Zero();
  double max_accel_ = 0;
  Eigen::Matrix3d prev_R_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d prev_w_ = Eigen::Vector3d::Zero();
  double max_alpha_ = 0;

  FollowerConfig Config(double accel) const {
    FollowerConfig c = FollowerConfig::FromYaml(DefaultDataDir() / "config" / "follower.yaml", transfer_.caps);
    if (accel > 0) {
      c.setpoint.max_linear_accel_m_s2 = accel;
      c.setpoint.max_angular_accel_rad_s2 = 2 * accel;  // 0.2 rad/s^2: the 1 deg/s cap stops in 87 ms
    }
    return c;
  }

  Eigen::Vector3d CmdP() const { return unit_.commanded_pose().translation(); }
  Eigen::Vector3d CmdV() const { return prev_v_; }
  Eigen::Matrix3d CmdR() const { return unit_.commanded_pose().linear(); }

  void Step() {
    clock_.AdvanceNs(kTickNs);
    ++tick_;
    if (tick_ % 10 == 0) {
      // Accelerate at half the cap, up to the speed cap.
      if (rotating_) {
        leader_w_ = std::min(w_cap_, leader_w_ + 0.5 * alpha_cap_ * 1e-3);
        leader_angle_ += leader_w_ * 1e-3;
      } else {
        leader_v_ = std::min(v_cap_, leader_v_ + 0.5 * a_cap_ * 1e-3);
        leader_s_ += leader_v_ * 1e-3;
      }
      if (leader_sending_) {
        const Eigen::Vector3d p = home_.translation() + leader_s_ * direction_;
        const Eigen::Vector3d v = leader_v_ * direction_;
        const Eigen::Vector3d w = leader_w_ * axis_;
        const Eigen::Quaterniond q(Eigen::AngleAxisd(leader_angle_, axis_));
        SetPointMessage m;
        m.sequence = ++sequence_;
        m.leader_session = 1;
        m.stamp_ns = clock_.now_ns();
        m.p_FM = {p.x(), p.y(), p.z()};
        m.q_FM = {q.w(), q.x(), q.y(), q.z()};
        m.twist_F = {v.x(), v.y(), v.z(), w.x(), w.y(), w.z()};
        m.flags = leader_flags_;
        link_.SendSetPoint(m);
        last_arrival_s_ = clock_.NowS();
      }
    }
    unit_.Tick();
    const Eigen::Vector3d v = (CmdP() - prev_p_) / kTickS;
    if (tick_ > 1) max_accel_ = std::max(max_accel_, (v - prev_v_).norm() / kTickS);
    prev_p_ = CmdP();
    prev_v_ = v;
    // The angular velocity in F: the rotation since the last tick, as a rotation vector, over the tick.
    const Eigen::AngleAxisd turn(CmdR() * prev_R_.transpose());
    const Eigen::Vector3d w = turn.angle() * turn.axis() / kTickS;
    if (tick_ > 1) max_alpha_ = std::max(max_alpha_, (w - prev_w_).norm() / kTickS);
    prev_R_ = CmdR();
    prev_w_ = w;
  }
  void Run(double seconds) {
    for (std::int64_t i = 0, n = std::llround(seconds / kTickS); i < n; ++i) Step();
  }
  // Enabled and cruising at the speed cap (the angular one when rotating_).
  void CruiseAtTheCap() {
    prev_p_ = CmdP();
    prev_R_ = CmdR();
    StateCommandMessage m;
    m.command = StateCommand::kEnable;
    ASSERT_TRUE(link_.operator_commands().Send(m));
    Run(0.05);
    ASSERT_EQ(unit_.state(), OperatingState::kEnabled);
    // The leader's ramp (2 v/a), then ten of the follower's time constants (v/a: it trails the set-point by the
    // distance it needs to stop, v^2 / 2a).
    Run(rotating_ ? 12.0 * w_cap_ / alpha_cap_ + 0.05 : 12.0 * v_cap_ / a_cap_ + 0.05);
    ASSERT_EQ(unit_.state(), OperatingState::kEnabled);
    ASSERT_EQ(unit_.counters().setpoints_rejected, 0u);
    if (rotating_) {
      ASSERT_GT(prev_w_.norm(), 0.99 * w_cap_);
    } else {
      ASSERT_GT(CmdV().norm(), 0.99 * v_cap_);
    }
  }
  // Steps until the commanded pose stands still for 10 ms (at most `max_s`); returns false if it never did.
  bool RunToRest(double max_s) {
    int still = 0;
    for (std::int64_t i = 0, n = std::llround(max_s / kTickS); i < n && still < 100; ++i) {
      Step();
      still = CmdV().norm() == 0.0 && prev_w_.norm() == 0.0 ? still + 1 : 0;
    }
    return still >= 100;
  }
  // Holding from here: comes to rest within the stopping distance of its velocity now at the acceleration cap, and
  // stays there while the leader's hand keeps moving.
  void ExpectStopsWithinTheCapAndStays() {
    const double v0 = CmdV().norm();
    const Eigen::Vector3d p0 = CmdP();
    ASSERT_TRUE(RunToRest(1.0));
    EXPECT_LE((CmdP() - p0).norm(), v0 * v0 / (2 * a_cap_) + v0 * kTickS + 1e-12);
    EXPECT_LE(max_accel_, a_cap_ * (1 + 1e-6));
    const Eigen::Vector3d p_rest = CmdP();
    Run(0.2);
    EXPECT_EQ(CmdP(), p_rest);
  }
};

TEST_P(FollowerHoldTest, ALeaderThatStopsAtTheSpeedCapHoldsWithin30MsAndStopsWithinTheCaps) {
  CruiseAtTheCap();
  leader_sending_ = false;
  const double t_last = last_arrival_s_;
  const Eigen::Vector3d p_stop = CmdP();
  while (unit_.state() == OperatingState::kEnabled && clock_.NowS() - t_last < 0.1) Step();
  EXPECT_EQ(unit_.state(), OperatingState::kReady);
  EXPECT_LE(clock_.NowS() - t_last, config_.watchdog.hold_after_s + 1.5 * kTickS);  // hold within 30 ms
  EXPECT_EQ(unit_.counters().watchdog_holds, 1u);
  const double v_hold = CmdV().norm();
  if (a_cap_ < 1.0) {
    EXPECT_GT(v_hold, 0.1 * v_cap_);  // still moving: the hold itself decelerates
  }
  const Eigen::Vector3d p_hold = CmdP();
  ASSERT_TRUE(RunToRest(1.0));
  // At most the cap's stopping distance (v^2 / 2a, plus a tick) beyond the last set-point's extrapolation, measured
  // from where the leader stopped; and after the hold began, at most the stopping distance from its velocity then.
  const double stop = v_cap_ * v_cap_ / (2 * a_cap_) + v_cap_ * kTickS;
  const double extrapolated = v_cap_ * (config_.watchdog.max_extrapolation_s + 1e-3);
  EXPECT_LE((CmdP() - p_stop).norm(), stop + extrapolated);
  EXPECT_LE((CmdP() - p_hold).norm(), v_hold * v_hold / (2 * a_cap_) + v_hold * kTickS + 1e-12);
  EXPECT_LE(max_accel_, a_cap_ * (1 + 1e-6));
  EXPECT_EQ(unit_.counters().limit_violations, 0u);
}

TEST_P(FollowerHoldTest, PresenceReleasedAtTheSpeedCapDeceleratesWithinTheCap) {
  CruiseAtTheCap();
  leader_flags_ = 0;  // the operator lets go; the set-points keep coming
  while (unit_.state() == OperatingState::kEnabled && tick_ < 100'000'000) Step();
  EXPECT_EQ(unit_.state(), OperatingState::kReady);
  ExpectStopsWithinTheCapAndStays();
  EXPECT_EQ(unit_.counters().limit_violations, 0u);
}

TEST_P(FollowerHoldTest, AHoldTowardsAStrokeLimitStopsAtIt) {
  // The leader's set-points run 20 mm below the robot (the follower re-anchored where it stood), so they stay
  // feasible while the robot itself is driven up into the upper strokes at the cap. The operator lets go closer to
  // the wall than the stopping distance: the deceleration would cross the limit, and stops at it instead.
  direction_ = Eigen::Vector3d::UnitZ();
  leader_s_ = -0.02;
  CruiseAtTheCap();
  const double stop = v_cap_ * v_cap_ / (2 * a_cap_);
  double min_margin = 1e9, v_release = 0;
  for (int i = 0; i < 200000 && leader_flags_ != 0; ++i) {
    Step();
    const double margin = robot::CalcInverseKinematics(model_, unit_.commanded_pose()).tightest().margin;
    min_margin = std::min(min_margin, margin);
    if (margin < 0.5 * stop) {
      leader_flags_ = 0;
      v_release = CmdV().norm();
    }
  }
  ASSERT_EQ(leader_flags_, 0) << "never came within half the stopping distance of a limit";
  EXPECT_GT(v_release, 0.5 * v_cap_);  // the hold began at speed, closer to the wall than it needs to stop
  ASSERT_TRUE(RunToRest(1.0));
  for (int i = 0; i < 1000; ++i) {
    Step();
    min_margin =
        std::min(min_margin, robot::CalcInverseKinematics(model_, unit_.commanded_pose()).tightest().margin);
  }
  EXPECT_GE(min_margin, 0.0);
  EXPECT_TRUE(robot::CalcInverseKinematics(model_, unit_.commanded_pose()).feasible);
  EXPECT_EQ(unit_.counters().limit_violations, 0u);
  EXPECT_GT(unit_.counters().guard_constrained, 0u);  // the guard, not the deceleration, stopped it at the wall
}

TEST_P(FollowerHoldTest, ALeaderThatStopsTurningAtTheAngularCapStopsWithinTheAngularCaps) {
  rotating_ = true;
  CruiseAtTheCap();
  leader_sending_ = false;
  const double t_last = last_arrival_s_;
  const Eigen::Matrix3d R_stop = CmdR();
  while (unit_.state() == OperatingState::kEnabled && clock_.NowS() - t_last < 0.1) Step();
  EXPECT_EQ(unit_.state(), OperatingState::kReady);
  EXPECT_LE(clock_.NowS() - t_last, config_.watchdog.hold_after_s + 1.5 * kTickS);
  const double w_hold = prev_w_.norm();
  if (alpha_cap_ < 1.0) {
    EXPECT_GT(w_hold, 0.1 * w_cap_);  // still turning: the hold itself decelerates
  }
  const Eigen::Matrix3d R_hold = CmdR();
  ASSERT_TRUE(RunToRest(1.0));
  const double stop = w_cap_ * w_cap_ / (2 * alpha_cap_) + w_cap_ * kTickS;
  const double extrapolated = w_cap_ * (config_.watchdog.max_extrapolation_s + 1e-3);
  EXPECT_LE(Eigen::AngleAxisd(CmdR() * R_stop.transpose()).angle(), stop + extrapolated);
  EXPECT_LE(Eigen::AngleAxisd(CmdR() * R_hold.transpose()).angle(),
            w_hold * w_hold / (2 * alpha_cap_) + w_hold * kTickS + 1e-9);
  EXPECT_LE(max_alpha_, alpha_cap_ * (1 + 1e-3));
  EXPECT_EQ(unit_.counters().limit_violations, 0u);
}

// A flight recorder that fails (a write error, a full disk) while the robot moves at the speed cap: the follower holds
// as the watchdog does, decelerating to rest within the acceleration cap, though the set-points keep coming, and it
// never follows again (nothing it would do could be recorded).
TEST_P(FollowerHoldTest, ARecorderFailureAtTheSpeedCapHoldsWithinTheCapsForGood) {
  std::atomic<bool> recorder_failed{false};
  unit_.WatchRecorder(&recorder_failed);
  CruiseAtTheCap();
  recorder_failed.store(true);
  Step();
  EXPECT_EQ(unit_.state(), OperatingState::kReady);  // holding from the next tick
  ExpectStopsWithinTheCapAndStays();                  // though the hand keeps moving, with presence
  EXPECT_EQ(unit_.state(), OperatingState::kReady);
  EXPECT_EQ(unit_.counters().setpoints_rejected, 0u);  // not the set-points' fault
}

// A record the recorder's queue has no room for is a motion unrecorded: the unit watching a recorder raises the
// failure flag itself and holds (a unit with no recorder watched only counts it).
TEST(FollowerRecorderTest, AFullRecordQueueHoldsTheRobot) {
  const ShippedFollowerSetup s;
  FollowerConfig config = s.ShippedFollowerConfig();
  config.recorder_capacity = 64;
  rt::SimulatedClock clock;
  InProcessLink link(clock);
  actuation::PulseRecorderFollower back_end(s.model_, s.actuation_, s.home_, 1 << 16, 1 << 16);
  FollowerUnit unit(s.model_, s.actuation_, config, back_end, link, clock);
  std::atomic<bool> recorder_failed{false};
  unit.WatchRecorder(&recorder_failed);
  StateCommandMessage enable;
  enable.command = StateCommand::kEnable;
  ASSERT_TRUE(link.operator_commands().Send(enable));
  std::uint64_t sequence = 0;
  const auto tick = [&](bool drain) {
    clock.AdvanceNs(kTickNs);
    if (clock.now_ns() % 1'000'000 == 0) {  // a 1 kHz leader holding still at home, with presence
      SetPointMessage m;
      m.sequence = ++sequence;
      m.leader_session = 1;
      m.stamp_ns = clock.now_ns();
      const Eigen::Vector3d p = s.home_.translation();
      const Eigen::Quaterniond q(s.home_.linear());
      m.p_FM = {p.x(), p.y(), p.z()};
      m.q_FM = {q.w(), q.x(), q.y(), q.z()};
      m.flags = kSetPointPresence;
      link.SendSetPoint(m);
    }
    unit.Tick();
    FollowerTickRecord r;
    while (drain && unit.TakeRecord(r)) {
    }
  };
  for (int i = 0; i < 500; ++i) tick(true);  // 50 ms, drained: it follows
  ASSERT_EQ(unit.state(), OperatingState::kEnabled);
  ASSERT_FALSE(recorder_failed.load());
  int ticks = 0;
  while (unit.state() == OperatingState::kEnabled && ticks < 1000) {
    tick(false);  // the recorder stalls
    ++ticks;
  }
  EXPECT_TRUE(recorder_failed.load());
  EXPECT_EQ(unit.state(), OperatingState::kReady);
  EXPECT_GT(unit.counters().records_dropped, 0u);
  for (int i = 0; i < 100; ++i) tick(true);  // the queue drains again: it still holds
  EXPECT_EQ(unit.state(), OperatingState::kReady);
}

INSTANTIATE_TEST_SUITE_P(AccelerationCaps, FollowerHoldTest, ::testing::Values(0.0, 0.1),
                         [](const ::testing::TestParamInfo<double>& info) {
                           return info.param > 0 ? std::string("Low") : std::string("Shipped");
                         });

}  // namespace
}  // namespace robossis::teleop
