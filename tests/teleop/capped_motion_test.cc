// The set-points' motion within the motors' top speeds: a move the speed caps allow but the linear motors (20 mm/s
// of stroke in the shipped actuation.yaml) cannot make is slowed to where the busiest motor is at its top speed,
// and the twist still changes within the acceleration caps on the way there.

#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "robot/rsr_kinematics.h"
#include "src/teleop/capped_motion.h"
#include "tests/teleop/follower_fixture.h"

namespace robossis::teleop {
namespace {

class CappedMotionTest : public ::testing::Test, protected ShippedFollowerSetup {
 protected:
  static constexpr double kDt = 1e-3;  // one set-point period
  SetPointLimits limits_ = RaisedCaps();
  robot::RsrJointVector max_joint_speed_ = MotorSpeeds();

  static SetPointLimits RaisedCaps() {
    SetPointLimits l;
    l.caps.max_linear_speed_m_s = 0.1;  // `--max-speed-mm-s 100`: 5 times the linear motors' stroke speed
    l.caps.max_angular_speed_rad_s = 0.2;
    return l;
  }
  robot::RsrJointVector MotorSpeeds() const {
    const auto speeds = actuation_.MaxJointSpeeds();
    return Eigen::Map<const robot::RsrJointVector>(speeds.data());
  }
  // The busiest motor's share of its top speed for `twist` at `X`.
  double Busiest(const Eigen::Isometry3d& X, const Vector6d& twist) const {
    return (robot::CalcJacobian(model_, X) * twist).cwiseQuotient(max_joint_speed_).lpNorm<Eigen::Infinity>();
  }
};

TEST_F(CappedMotionTest, AMoveTooFastForTheMotorsSettlesAtTheBusiestMotorsTopSpeedWithinTheAccelerationCaps) {
  Eigen::Isometry3d X = home_;
  Vector6d twist = Vector6d::Zero();
  Vector6d target_step = Vector6d::Zero();
  target_step[2] = 0.03;  // 30 mm along z: three linear motors' stroke
  double busiest_late = 0;
  for (int k = 0; k < 200; ++k) {
    const Matrix6d rows = MotorRows(model_, X, max_joint_speed_);
    const Vector6d next = NextCappedTwist(twist, target_step - robot::TwistStepBetween(home_, X), limits_, kDt, rows);
    EXPECT_LE((next - twist).head<3>().norm(), limits_.max_linear_accel_m_s2 * kDt * (1 + 1e-9)) << k;
    EXPECT_LE((next - twist).tail<3>().norm(), limits_.max_angular_accel_rad_s2 * kDt * (1 + 1e-9)) << k;
    twist = next;
    X = robot::ApplyTwistStep(X, twist * kDt);
    if (k >= 100) busiest_late = std::max(busiest_late, Busiest(X, twist));
  }
  // Past the acceleration (5 m/s^2 reaches 20 mm/s in 4 ms), the busiest motor runs at its top speed (within the
  // Jacobian's change over one period), and the move is far below the 100 mm/s the caps allow.
  EXPECT_LE(busiest_late, 1.0 + 1e-3);
  EXPECT_GE(busiest_late, 0.99);
  EXPECT_LT(twist.head<3>().norm(), 0.5 * limits_.caps.max_linear_speed_m_s);
  EXPECT_GT(twist.head<3>().norm(), 0.005);
}

TEST_F(CappedMotionTest, WithoutABoundTheMoveRunsAtTheSpeedCapBeyondTheMotors) {
  Vector6d twist = Vector6d::Zero();
  Vector6d target_step = Vector6d::Zero();
  target_step[2] = 0.03;
  const Matrix6d no_bound = MotorRows(model_, home_, Vector6d::Constant(std::numeric_limits<double>::infinity()));
  EXPECT_EQ(no_bound, Matrix6d::Zero());
  for (int k = 0; k < 50; ++k) {
    const Vector6d next = NextCappedTwist(twist, target_step, limits_, kDt, no_bound);
    EXPECT_EQ(next, NextCappedTwist(twist, target_step, limits_, kDt)) << k;  // the plain form
    twist = next;
  }
  EXPECT_NEAR(twist.head<3>().norm(), limits_.caps.max_linear_speed_m_s, 1e-12);
  EXPECT_GT(Busiest(home_, twist), 2.0);  // what the leader sent before it knew the motors' speeds
}

}  // namespace
}  // namespace robossis::teleop
