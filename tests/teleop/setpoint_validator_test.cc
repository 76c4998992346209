#include "src/teleop/setpoint_validator.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "robot/rsr_model.h"
#include "src/core/units.h"
#include "tests/support/alloc_counter.h"

namespace robossis::teleop {
namespace {

class SetPointValidatorTest : public ::testing::Test {
 protected:
  const robot::RsrModel model_ = robot::RsrModel::Default();
  const Eigen::Isometry3d home_ = model_.geometry().X_FM_home;
  SetPointLimits limits_;  // 10 mm/s, 1 deg/s, 30 ms

  SetPointMessage Message(std::uint64_t seq, double t_s, const Eigen::Vector3d& dp = Eigen::Vector3d::Zero(),
                          const Eigen::Vector3d& v = Eigen::Vector3d::Zero()) const {
    SetPointMessage m;
    m.sequence = seq;
    m.leader_session = 7;
    m.stamp_ns = static_cast<std::int64_t>(std::llround(t_s * 1e9));
    const Eigen::Vector3d p = home_.translation() + dp;
    m.p_FM = {p.x(), p.y(), p.z()};
    m.twist_F = {v.x(), v.y(), v.z(), 0, 0, 0};
    m.flags = kSetPointPresence;
    return m;
  }
};

TEST_F(SetPointValidatorTest, AcceptsASlowMotionInsideTheWorkspace) {
  SetPointValidator v(model_, limits_);
  SetPointSample s;
  for (int k = 0; k < 1000; ++k) {
    const double t = 1e-3 * k;
    const SetPointMessage m = Message(k + 1, t, Eigen::Vector3d(0.005 * t, 0, 0), Eigen::Vector3d(0.005, 0, 0));
    ASSERT_EQ(v.CheckMessage(m, t, t + 1e-4, s), SetPointVerdict::kAccepted) << k;
  }
  EXPECT_EQ(v.count(SetPointVerdict::kAccepted), 1000u);
  EXPECT_EQ(v.rejected(), 0u);
}

TEST_F(SetPointValidatorTest, RejectsNaNInfinityAndANonUnitQuaternion) {
  SetPointValidator v(model_, limits_);
  SetPointSample s;
  SetPointMessage m = Message(1, 0);
  m.p_FM[1] = std::nan("");
  EXPECT_EQ(v.CheckMessage(m, 0, 0, s), SetPointVerdict::kNotFinite);
  m = Message(2, 0);
  m.twist_F[4] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(v.CheckMessage(m, 0, 0, s), SetPointVerdict::kNotFinite);
  m = Message(3, 0);
  m.q_FM = {0.9, 0, 0, 0};
  EXPECT_EQ(v.CheckMessage(m, 0, 0, s), SetPointVerdict::kNotFinite);
  EXPECT_EQ(v.count(SetPointVerdict::kNotFinite), 3u);
}

TEST_F(SetPointValidatorTest, RejectsAStaleSetPoint) {
  SetPointValidator v(model_, limits_);
  SetPointSample s;
  EXPECT_EQ(v.CheckMessage(Message(1, 0), 0.0, 0.031, s), SetPointVerdict::kStale);
  EXPECT_EQ(v.CheckMessage(Message(2, 0), 0.0, 0.029, s), SetPointVerdict::kAccepted);
}

TEST_F(SetPointValidatorTest, RejectsOutOfOrderAndReanchorsANewSession) {
  SetPointValidator v(model_, limits_);
  SetPointSample s;
  ASSERT_EQ(v.CheckMessage(Message(5, 0.000), 0.000, 0.000, s), SetPointVerdict::kAccepted);
  EXPECT_EQ(v.CheckMessage(Message(5, 0.001), 0.001, 0.001, s), SetPointVerdict::kOutOfOrder);
  EXPECT_EQ(v.CheckMessage(Message(4, 0.002), 0.002, 0.002, s), SetPointVerdict::kOutOfOrder);
  // A restarted leader (new session) with a far pose: no rate is judged across sessions.
  SetPointMessage m = Message(1, 0.003, Eigen::Vector3d(0.02, 0, 0));
  m.leader_session = 8;
  EXPECT_EQ(v.CheckMessage(m, 0.003, 0.003, s), SetPointVerdict::kAccepted);
}

TEST_F(SetPointValidatorTest, RejectsAPoseOutsideTheWorkspaceByTheExactIk) {
  SetPointValidator v(model_, limits_);
  SetPointSample s;
  EXPECT_EQ(v.CheckMessage(Message(1, 0, Eigen::Vector3d(0, 0, 0.08)), 0, 0, s), SetPointVerdict::kInfeasible);
  // A tilt past the spherical cones (+/-25 deg) with strokes in range.
  SetPointMessage m = Message(2, 0);
  const Eigen::Quaterniond q(RotationFromRpy(Eigen::Vector3d(DegToRad(27), 0, 0)));
  m.q_FM = {q.w(), q.x(), q.y(), q.z()};
  EXPECT_EQ(v.CheckMessage(m, 0, 0, s), SetPointVerdict::kInfeasible);
  EXPECT_EQ(v.tightest().joint, robot::RsrJointKind::kSphericalCone);
}

TEST_F(SetPointValidatorTest, RejectsATwistOrAPoseChangeAboveTheCaps) {
  SetPointValidator v(model_, limits_);
  SetPointSample s;
  // The stated twist: 12 mm/s against 10 mm/s.
  EXPECT_EQ(v.CheckMessage(Message(1, 0, Eigen::Vector3d::Zero(), Eigen::Vector3d(0.012, 0, 0)), 0, 0, s),
            SetPointVerdict::kTooFast);
  ASSERT_EQ(v.CheckMessage(Message(2, 0), 0, 0, s), SetPointVerdict::kAccepted);
  // A pose that moved 20 µm in 1 ms (20 mm/s) while claiming to stand still.
  EXPECT_EQ(v.CheckMessage(Message(3, 0.001, Eigen::Vector3d(20e-6, 0, 0)), 0.001, 0.001, s),
            SetPointVerdict::kTooFast);
  // The clinical caps: 5 mm/s is too fast.
  SetPointLimits clinical = limits_;
  clinical.caps = transfer::ClinicalSpeedCaps();
  SetPointValidator vc(model_, clinical);
  EXPECT_EQ(vc.CheckMessage(Message(1, 0, Eigen::Vector3d::Zero(), Eigen::Vector3d(0.005, 0, 0)), 0, 0, s),
            SetPointVerdict::kTooFast);
}

TEST_F(SetPointValidatorTest, JudgesThePoseChangeOverTheSequenceStepsNotTheJitteredStamps) {
  SetPointValidator v(model_, limits_);
  SetPointSample s;
  const Eigen::Vector3d cap_speed(0.010, 0, 0);  // 10 mm/s: 10 um per 1 ms set-point period
  // A leader tick sampled its device 0.4 ms late, the next one on time: stamps 0.6 ms apart, one period of motion.
  const double stamps[] = {0.000, 0.0014, 0.0020, 0.0030};
  for (int k = 0; k < 4; ++k) {
    const SetPointMessage m = Message(k + 1, stamps[k], cap_speed * (1e-3 * k), cap_speed);
    EXPECT_EQ(v.CheckMessage(m, stamps[k], stamps[k], s), SetPointVerdict::kAccepted) << k;
  }
  // Neither a forged sequence jump (1000 steps in 1 ms of stamps) nor a forged stamp (1 s for one step) buys 1 mm.
  const Eigen::Vector3d far = cap_speed * 3e-3 + Eigen::Vector3d(1e-3, 0, 0);
  EXPECT_EQ(v.CheckMessage(Message(1004, 0.0040, far, cap_speed), 0.004, 0.004, s), SetPointVerdict::kTooFast);
  EXPECT_EQ(v.CheckMessage(Message(5, 1.0030, far, cap_speed), 1.003, 1.003, s), SetPointVerdict::kTooFast);
}

TEST_F(SetPointValidatorTest, AForgedStampAndSequenceBuyNoLongerStepThanTheFollowersOwnClock) {
  SetPointValidator v(model_, limits_);
  SetPointSample s;
  ASSERT_EQ(v.CheckMessage(Message(1, 0.0), 0.0, 0.0, s), SetPointVerdict::kAccepted);
  // Stamp and sequence both jump by 1e9 (1e9 periods; 1 s of stamps) per message, arriving at 1 kHz on the
  // follower's clock, each 1 mm farther: 1 m/s against the 10 mm/s cap.
  const double step_m = 1e-3;
  std::uint64_t accepted = 0;
  for (int k = 1; k <= 100; ++k) {
    const double arrival = 1e-3 * k;
    const SetPointMessage m = Message(1 + 1'000'000'000ull * k, 1.0 * k, Eigen::Vector3d(step_m * k, 0, 0));
    const SetPointVerdict verdict = v.CheckMessage(m, arrival, arrival, s);
    EXPECT_EQ(verdict, SetPointVerdict::kTooFast) << k;
    if (verdict == SetPointVerdict::kAccepted) ++accepted;
  }
  EXPECT_EQ(accepted, 0u);
  // What an honest leader at the cap does over the same 100 ms of the follower's clock is still accepted.
  SetPointValidator honest(model_, limits_);
  const Eigen::Vector3d cap_speed(0.010, 0, 0);
  for (int k = 0; k <= 100; ++k) {
    const double t = 1e-3 * k;
    ASSERT_EQ(honest.CheckMessage(Message(k + 1, t, cap_speed * t, cap_speed), t, t, s), SetPointVerdict::kAccepted)
        << k;
  }
}

TEST_F(SetPointValidatorTest, ForgedIntervalsNeverBuyAFasterSustainedSpeed) {
  // Twice the cap, every step just inside what the per-step bound allows: the follower's credit (its own elapsed
  // time plus arrival_allowance_s once) runs out, so the distance accepted is bounded by the cap over that time.
  SetPointValidator v(model_, limits_);
  SetPointSample s;
  const double cap = limits_.caps.max_linear_speed_m_s;
  ASSERT_EQ(v.CheckMessage(Message(1, 0.0), 0.0, 0.0, s), SetPointVerdict::kAccepted);
  double x = 0;
  for (int k = 1; k <= 1000; ++k) {
    const double arrival = 1e-3 * k;
    const SetPointMessage m = Message(1 + 1'000'000'000ull * k, 1.0 * k, Eigen::Vector3d(x + 2 * cap * 1e-3, 0, 0));
    if (v.CheckMessage(m, arrival, arrival, s) == SetPointVerdict::kAccepted) x += 2 * cap * 1e-3;
  }
  EXPECT_LE(x, (1 + limits_.cap_tolerance) * cap * (1.0 + limits_.arrival_allowance_s) + 1e-12);
  EXPECT_GT(x, 0.9 * cap * 1.0);  // and about the cap's worth was accepted: not a blanket refusal
}

TEST_F(SetPointValidatorTest, StampsAtTheEndsOfInt64AreJudgedWithoutOverflow) {
  SetPointValidator v(model_, limits_);
  SetPointSample s;
  SetPointMessage m = Message(1, 0.0);
  m.stamp_ns = std::numeric_limits<std::int64_t>::min();
  ASSERT_EQ(v.CheckMessage(m, 0.0, 0.0, s), SetPointVerdict::kAccepted);
  m = Message(2, 0.0, Eigen::Vector3d(1e-3, 0, 0));
  m.stamp_ns = std::numeric_limits<std::int64_t>::max();  // 292 years of stamps for one period of motion
  EXPECT_EQ(v.CheckMessage(m, 1e-3, 1e-3, s), SetPointVerdict::kTooFast);
}

TEST_F(SetPointValidatorTest, RejectsAJumpInVelocity) {
  SetPointValidator v(model_, limits_);
  SetPointSample s;
  ASSERT_EQ(v.CheckMessage(Message(1, 0), 0, 0, s), SetPointVerdict::kAccepted);
  // 0 -> 9 mm/s in 1 ms: 9 m/s^2 against 5 m/s^2.
  EXPECT_EQ(v.CheckMessage(Message(2, 0.001, Eigen::Vector3d(9e-6, 0, 0), Eigen::Vector3d(0.009, 0, 0)), 0.001,
                           0.001, s),
            SetPointVerdict::kTooAccelerating);
}

TEST_F(SetPointValidatorTest, ZeroCapsAllowNoMotionAtAll) {
  SetPointLimits still = limits_;
  still.caps.max_linear_speed_m_s = 0;  // 0 is a value: standing still
  SetPointValidator v(model_, still);
  SetPointSample s;
  EXPECT_EQ(v.CheckMessage(Message(1, 0, Eigen::Vector3d::Zero(), Eigen::Vector3d(1e-6, 0, 0)), 0, 0, s),
            SetPointVerdict::kTooFast);
}

TEST_F(SetPointValidatorTest, CheckAllocatesNothing) {
  SetPointValidator v(model_, limits_);
  SetPointSample s;
  testing::AllocationCounter counter;
  for (int k = 0; k < 100; ++k) v.CheckMessage(Message(k + 1, 1e-3 * k), 1e-3 * k, 1e-3 * k, s);
  EXPECT_EQ(counter.count(), 0u);
}

}  // namespace
}  // namespace robossis::teleop
