// The follower's hold: from the speed cap, the commanded motion decelerates to rest within the acceleration cap
// (the validator's), reaches the hold state within the watchdog's 30 ms, and never crosses a joint limit.
#include <algorithm>
#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "robot/actuation/pulse_recorder_follower.h"
#include "src/core/config.h"
#include "src/teleop/follower_unit.h"
#include "src/teleop/in_process_link.h"

namespace robossis::teleop {
namespace {

constexpr std::int64_t kTickNs = 100'000;  // 10 kHz
constexpr double kTickS = 1e-4;

// A follower unit on the simulated clock with the pulse recorder, and a 1 kHz leader that ramps its velocity up
// to the speed cap along `direction_` within the acceleration cap (so that the validator accepts every set-point),
// then cruises. The acceleration cap is the test's parameter: the shipped one (the stop takes 2 ms) and a low one
// (0.1 m/s^2: the stop takes 0.1 s, longer than the watchdog's 30 ms, so the hold itself decelerates).
class FollowerHoldTest : public ::testing::TestWithParam<double> {
 protected:
  const robot::RsrModel model_ = robot::RsrModel::Default();
  const Eigen::Isometry3d home_ = model_.geometry().X_FM_home;
  const actuation::ActuationConfig actuation_ =
      actuation::ActuationConfig::FromYaml(DefaultDataDir() / "config" / "actuation.yaml");
  const transfer::TransferConfig transfer_ =
      transfer::TransferConfig::FromYaml(DefaultDataDir() / "config" / "transfer.yaml");
  FollowerConfig config_ = Config(GetParam());
  const double v_cap_ = config_.setpoint.caps.max_linear_speed_m_s;
  const double a_cap_ = config_.setpoint.max_linear_accel_m_s2;
  rt::SimulatedClock clock_;
  InProcessLink link_{clock_};
  actuation::PulseRecorderFollower back_end_{model_, actuation_, home_, 1 << 16, 1 << 16};
  FollowerUnit unit_{model_, actuation_, config_, back_end_, link_, clock_};

  Eigen::Vector3d direction_ = Eigen::Vector3d::UnitX();
  double leader_s_ = 0, leader_v_ = 0;  // the leader's distance along direction_ and its speed
  std::uint8_t leader_flags_ = kSetPointPresence;
  bool leader_sending_ = true;
  std::uint64_t sequence_ = 0;
  std::int64_t tick_ = 0;
  double last_arrival_s_ = 0;
  // The commanded position's history, for the finite-difference velocity and acceleration.
  Eigen::Vector3d prev_p_ = Eigen::Vector3d::Zero(), prev_v_ = Eigen::Vector3d::Zero();
  double max_accel_ = 0;

  FollowerConfig Config(double accel) const {
    FollowerConfig c = FollowerConfig::FromYaml(DefaultDataDir() / "config" / "follower.yaml", transfer_.caps);
    if (accel > 0) c.setpoint.max_linear_accel_m_s2 = accel;
    return c;
  }

  Eigen::Vector3d CmdP() const { return unit_.commanded_pose().translation(); }
  Eigen::Vector3d CmdV() const { return prev_v_; }

  void Step() {
    clock_.AdvanceNs(kTickNs);
    ++tick_;
    if (tick_ % 10 == 0) {
      // Accelerate at half the cap, up to the speed cap.
      leader_v_ = std::min(v_cap_, leader_v_ + 0.5 * a_cap_ * 1e-3);
      leader_s_ += leader_v_ * 1e-3;
      if (leader_sending_) {
        const Eigen::Vector3d p = home_.translation() + leader_s_ * direction_;
        const Eigen::Vector3d v = leader_v_ * direction_;
        SetPointMessage m;
        m.sequence = ++sequence_;
        m.leader_session = 1;
        m.stamp_ns = clock_.now_ns();
        m.p_FM = {p.x(), p.y(), p.z()};
        m.twist_F = {v.x(), v.y(), v.z(), 0, 0, 0};
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
  }
  void Run(double seconds) {
    for (std::int64_t i = 0, n = std::llround(seconds / kTickS); i < n; ++i) Step();
  }
  // Enabled and cruising at the speed cap.
  void CruiseAtTheCap() {
    prev_p_ = CmdP();
    StateCommandMessage m;
    m.command = StateCommand::kEnable;
    ASSERT_TRUE(link_.operator_commands().Send(m));
    Run(0.05);
    ASSERT_EQ(unit_.state(), OperatingState::kEnabled);
    // The leader's ramp (2 v/a), then ten of the follower's time constants (v/a: it trails the set-point by the
    // distance it needs to stop, v^2 / 2a).
    Run(12.0 * v_cap_ / a_cap_ + 0.05);
    ASSERT_EQ(unit_.state(), OperatingState::kEnabled);
    ASSERT_EQ(unit_.counters().setpoints_rejected, 0u);
    ASSERT_GT(CmdV().norm(), 0.99 * v_cap_);
  }
  // Steps until the commanded pose stands still for 10 ms (at most `max_s`); returns false if it never did.
  bool RunToRest(double max_s) {
    int still = 0;
    for (std::int64_t i = 0, n = std::llround(max_s / kTickS); i < n && still < 100; ++i) {
      Step();
      still = CmdV().norm() == 0.0 ? still + 1 : 0;
    }
    return still >= 100;
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
  const double v0 = CmdV().norm();
  const Eigen::Vector3d p0 = CmdP();
  ASSERT_TRUE(RunToRest(1.0));
  EXPECT_LE((CmdP() - p0).norm(), v0 * v0 / (2 * a_cap_) + v0 * kTickS + 1e-12);
  EXPECT_LE(max_accel_, a_cap_ * (1 + 1e-6));
  // At rest it stays at rest while the leader's hand keeps moving.
  const Eigen::Vector3d p_rest = CmdP();
  Run(0.2);
  EXPECT_EQ(CmdP(), p_rest);
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

INSTANTIATE_TEST_SUITE_P(AccelerationCaps, FollowerHoldTest, ::testing::Values(0.0, 0.1),
                         [](const ::testing::TestParamInfo<double>& info) {
                           return info.param > 0 ? std::string("Low") : std::string("Shipped");
                         });

}  // namespace
}  // namespace robossis::teleop
