#include "robot/sigma7_model.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "src/core/pose.h"
#include "src/core/units.h"

namespace robossis::robot {
namespace {

class Sigma7Test : public ::testing::Test {
 protected:
  const Sigma7Model model_ = Sigma7Model::Default();
};

// eq. 2–4 hold for the IK solution: the chain-frame coordinates of P are reproduced by the joint angles.
TEST_F(Sigma7Test, IkSatisfiesPaperEquations) {
  const Sigma7Geometry& g = model_.geometry();
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  int tested = 0;
  for (int k = 0; k < 1000; ++k) {
    const Eigen::Vector3d p = model_.p_center_O() + Eigen::Vector3d(u(gen), u(gen), u(gen));
    const DeltaIkResult ik = CalcDeltaInverseKinematics(model_, p);
    if (!ik.reachable) continue;
    ++tested;
    for (int i = 0; i < kNumDeltaChains; ++i) {
      const Eigen::Vector3d P = ChainCoordinates(model_, i, p);
      const double t1 = ik.joints.theta1[i], t2 = ik.joints.theta2[i], t3 = ik.joints.theta3[i];
      EXPECT_NEAR(P.x(), g.a_m * std::cos(t1) - g.c_m + g.b_m * std::sin(t3) * std::cos(t2), 1e-12);  // eq. 2
      EXPECT_NEAR(P.y(), g.b_m * std::cos(t3) - g.f_m, 1e-12);                                         // eq. 3
      EXPECT_NEAR(P.z(), g.a_m * std::sin(t1) + g.b_m * std::sin(t3) * std::sin(t2), 1e-12);          // eq. 4
      EXPECT_GT(t3, 0.0);  // the physical branch, paper §III-A
    }
  }
  EXPECT_GT(tested, 500);
}

TEST_F(Sigma7Test, IkFkRoundTrip) {
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> u(-0.06, 0.06);
  int tested = 0;
  for (int k = 0; k < 5000; ++k) {
    const Eigen::Vector3d p = model_.p_center_O() + Eigen::Vector3d(u(gen), u(gen), u(gen));
    const DeltaIkResult ik = CalcDeltaInverseKinematics(model_, p);
    if (!ik.within_limits) continue;
    ++tested;
    const DeltaFkResult fk = CalcDeltaForwardKinematics(model_, ik.joints.theta1);
    ASSERT_TRUE(fk.ok);
    EXPECT_LE((fk.p_O - p).norm(), 1e-10);
  }
  EXPECT_GT(tested, 1000);
}

TEST_F(Sigma7Test, FkIkRoundTripFromJointAngles) {
  std::mt19937 gen{9};
  std::uniform_real_distribution<double> t(DegToRad(0), DegToRad(70));
  for (int k = 0; k < 1000; ++k) {
    const Eigen::Vector3d theta1(t(gen), t(gen), t(gen));
    const DeltaFkResult fk = CalcDeltaForwardKinematics(model_, theta1);
    if (!fk.ok) continue;
    const DeltaIkResult ik = CalcDeltaInverseKinematics(model_, fk.p_O);
    ASSERT_TRUE(ik.reachable);
    EXPECT_LE((ik.joints.theta1 - theta1).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST_F(Sigma7Test, UnreachablePointsAreReported) {
  EXPECT_FALSE(CalcDeltaInverseKinematics(model_, Eigen::Vector3d(1.0, 0, 0)).reachable);
  EXPECT_FALSE(CalcDeltaInverseKinematics(model_, Eigen::Vector3d::Constant(std::nan(""))).reachable);
}

// Paper §III-C: wrist ranges 235 x 140 x 200 deg (yaw x pitch x roll, centred; the config).
TEST_F(Sigma7Test, WristRanges) {
  EXPECT_TRUE(WristWithinRange(model_, Eigen::Vector3d(DegToRad(99), DegToRad(69), DegToRad(117))));
  EXPECT_FALSE(WristWithinRange(model_, Eigen::Vector3d(DegToRad(101), 0, 0)));
  EXPECT_FALSE(WristWithinRange(model_, Eigen::Vector3d(0, DegToRad(71), 0)));
  EXPECT_FALSE(WristWithinRange(model_, Eigen::Vector3d(0, 0, DegToRad(118))));
  const Eigen::Matrix3d R = RotationFromRpy(Eigen::Vector3d(0.3, -0.5, 1.2));
  EXPECT_TRUE(IsInSigma7Workspace(model_, model_.p_center_O(), R));
  EXPECT_FALSE(IsInSigma7Workspace(model_, model_.p_center_O() + Eigen::Vector3d(0.5, 0, 0), R));
}

}  // namespace
}  // namespace robossis::robot
