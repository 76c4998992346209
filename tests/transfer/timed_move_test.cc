// eq. 9 time-controlled moves: exact endpoints, continuous velocity, the peak speed of the trigonometric profile.

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "haptics/transfer/timed_move.h"
#include "src/core/units.h"

namespace robossis::transfer {
namespace {

TimedMoveRequest RandomRequest(std::mt19937& gen) {
  std::uniform_real_distribution<double> p(-0.02, 0.02), r(-0.2, 0.2);
  TimedMoveRequest req;
  req.delta_p_F = Eigen::Vector3d(p(gen), p(gen), p(gen));
  req.delta_rot_F = Eigen::Vector3d(r(gen), r(gen), r(gen));
  req.start_time_s = 0.5;
  return req;
}

Eigen::Isometry3d Start() { return PoseFromMmDeg((Vector6d() << 5, -3, 290, 2, -1, 4).finished()); }

TEST(TimedMoveTest, EndpointsAreExact) {
  std::mt19937 gen{42};
  for (int i = 0; i < 100; ++i) {
    const TimedMoveRequest req = RandomRequest(gen);
    const TimedMove move(Start(), req, 3.0);
    const RsrSetPoint before = move.Evaluate(0.2);
    const RsrSetPoint after = move.Evaluate(move.end_time_s());
    EXPECT_TRUE(before.X_FM.isApprox(Start(), 0.0));  // eq. 9, t < t0: x0 exactly
    // eq. 9, t >= t0 + dt: x0 + dx exactly (bit for bit the end pose computed once from the whole change).
    EXPECT_EQ(after.X_FM.translation(), Start().translation() + req.delta_p_F);
    EXPECT_EQ(after.X_FM.linear(), RotationFromVector(req.delta_rot_F) * Start().linear());
    EXPECT_EQ(after.velocity, Vector6d::Zero());
    EXPECT_EQ(move.Evaluate(100.0).X_FM.matrix(), after.X_FM.matrix());
  }
}

TEST(TimedMoveTest, VelocityIsContinuousAndMatchesTheFiniteDifference) {
  std::mt19937 gen{42};
  const TimedMoveRequest req = RandomRequest(gen);
  const TimedMove move(Start(), req, 2.0);
  const double dt = 1e-4;
  Vector6d prev_v = Vector6d::Zero();
  Vector6d prev_x = move.Evaluate(0).displacement;
  double max_dv = 0;
  for (double t = dt; t < 3.0; t += dt) {
    const RsrSetPoint sp = move.Evaluate(t);
    max_dv = std::max(max_dv, (sp.velocity - prev_v).norm());
    // The velocity is the derivative of the displacement (central estimate over the step).
    const Vector6d fd = (sp.displacement - prev_x) / dt;
    EXPECT_LT((fd - 0.5 * (sp.velocity + prev_v)).norm(), 1e-6);
    prev_v = sp.velocity;
    prev_x = sp.displacement;
  }
  // Largest velocity change per step: |a_max| dt = dx pi^2 / (2 dt^2) * dt, no jumps.
  const double a_max = Vector6d((Vector6d() << req.delta_p_F, req.delta_rot_F).finished()).norm() * kPi * kPi / 8.0;
  EXPECT_LE(max_dv, a_max * dt * 1.0001);
}

TEST(TimedMoveTest, PeakSpeedIsPiOverTwoTimesDxOverDt) {
  TimedMoveRequest req;
  req.delta_p_F = Eigen::Vector3d(0, 0, 0.010);
  const TimedMove move(Eigen::Isometry3d::Identity(), req, 5.0);
  // eq. 9 derivative at mid-move: dx/2 · pi/dt.
  EXPECT_NEAR(move.Evaluate(2.5).velocity.head<3>().norm(), kPi / 2 * 0.010 / 5.0, 1e-15);
  EXPECT_DOUBLE_EQ(move.peak_linear_speed_m_s(), kPi / 2 * 0.010 / 5.0);
}

TEST(TimedMoveTest, DurationFromSpeedMeetsTheSlowestDof) {
  TimedMoveRequest req;
  req.delta_p_F = Eigen::Vector3d(0.010, 0, 0);
  req.delta_rot_F = Eigen::Vector3d(0, 0, DegToRad(2));
  const double d = TimedMove::DurationForPeakSpeeds(req, 0.005, DegToRad(1));
  const TimedMove move(Eigen::Isometry3d::Identity(), req, d);
  EXPECT_LE(move.peak_linear_speed_m_s(), 0.005 * (1 + 1e-12));
  EXPECT_LE(move.peak_angular_speed_rad_s(), DegToRad(1) * (1 + 1e-12));
  EXPECT_NEAR(std::max(move.peak_linear_speed_m_s() / 0.005, move.peak_angular_speed_rad_s() / DegToRad(1)), 1.0,
              1e-12);
}

TEST(TimedMoveTest, SingleDofMoveLeavesTheOthersAlone) {
  TimedMoveRequest req;
  req.delta_rot_F = Eigen::Vector3d(0, DegToRad(3), 0);
  const TimedMove move(Start(), req, 1.0);
  for (double t : {0.1, 0.4, 0.9}) {
    const RsrSetPoint sp = move.Evaluate(t);
    EXPECT_EQ(sp.X_FM.translation(), Start().translation());
    EXPECT_EQ(sp.velocity.head<3>(), Eigen::Vector3d::Zero());
  }
}

TEST(TimedMoveTest, RejectsBadDurations) {
  TimedMoveRequest req;
  req.delta_p_F = Eigen::Vector3d(0.01, 0, 0);
  EXPECT_THROW(TimedMove(Eigen::Isometry3d::Identity(), req, 0.0), std::invalid_argument);
  EXPECT_THROW(TimedMove(Eigen::Isometry3d::Identity(), req, -1.0), std::invalid_argument);
  EXPECT_THROW(TimedMove(Eigen::Isometry3d::Identity(), req, std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace robossis::transfer
