#include "robot/rsr_kinematics.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "src/core/units.h"
#include "tests/support/alloc_counter.h"

namespace robossis::robot {
namespace {

class RsrKinematicsTest : public ::testing::Test {
 protected:
  const RsrModel model_ = RsrModel::Default();
  const Eigen::Isometry3d home_ = model_.geometry().X_FM_home;

  // A random pose around home, within (roughly) the reach of the assumed geometry (README.md).
  Eigen::Isometry3d RandomPose(std::mt19937& gen) const {
    std::uniform_real_distribution<double> pos(-0.13, 0.13), z(-0.07, 0.07), ang(-DegToRad(25), DegToRad(25));
    Eigen::Isometry3d X = home_;
    X.translation() += Eigen::Vector3d(pos(gen), pos(gen), z(gen));
    X.linear() = RotationFromRpy(Eigen::Vector3d(ang(gen), ang(gen), 1.6 * ang(gen)));
    return X;
  }
};

// The assumed geometry (README.md): at home every arm is at mid-stroke, 284 mm, with theta = psi = 0.
TEST_F(RsrKinematicsTest, HomePoseIsMidStroke) {
  const RsrIkResult ik = CalcInverseKinematics(model_, home_);
  EXPECT_TRUE(ik.feasible);
  for (int i = 0; i < kNumArms; ++i) {
    EXPECT_NEAR(ik.joints.d_m[i], 0.284, 1e-12);
    EXPECT_NEAR(ik.joints.theta_rad[i], 0.0, 1e-12);
    EXPECT_NEAR(ik.joints.psi_rad[i], 0.0, 1e-12);
    EXPECT_NEAR(ik.joints.cone_rad[i], 0.0, 1e-6);
  }
}

// eq. 6–8 as printed: d = |p + R b - a|, psi = asin(radial / d), theta = asin(-tangential / (d cos psi)).
TEST_F(RsrKinematicsTest, MatchesPaperEquationsAsPrinted) {
  std::mt19937 gen{42};
  for (int k = 0; k < 1000; ++k) {
    const Eigen::Isometry3d X = RandomPose(gen);
    const RsrIkResult ik = CalcInverseKinematics(model_, X);
    for (int i = 0; i < kNumArms; ++i) {
      const double g = model_.geometry().arm_angles_rad[i];
      const Eigen::Vector3d l = X * model_.p_MB(i) - model_.p_FA(i);  // (x - x_i, y - y_i, z - z_i)
      const double d = std::sqrt(l.x() * l.x() + l.y() * l.y() + l.z() * l.z());                  // eq. 6
      const double psi = std::asin((std::cos(g) * l.x() + std::sin(g) * l.y()) / d);              // eq. 8
      const double theta = std::asin((std::sin(g) * l.x() - std::cos(g) * l.y()) / (d * std::cos(psi)));  // eq. 7
      EXPECT_NEAR(ik.joints.d_m[i], d, 1e-12);
      EXPECT_NEAR(ik.joints.psi_rad[i], psi, 1e-9);
      EXPECT_NEAR(ik.joints.theta_rad[i], theta, 1e-9);
    }
  }
}

TEST_F(RsrKinematicsTest, ForwardOfInverseIsIdentityOverTenThousandPoses) {
  std::mt19937 gen{42};
  int tested = 0;
  double worst_p = 0, worst_r = 0;
  while (tested < 10000) {
    const Eigen::Isometry3d X = RandomPose(gen);
    const RsrIkResult ik = CalcInverseKinematics(model_, X);
    if (!ik.feasible) continue;
    ++tested;
    const RsrFkResult fk = CalcForwardKinematics(model_, ik.joints.actuated(), home_);
    ASSERT_TRUE(fk.converged()) << "pose " << tested << ": " << ToString(fk.status);
    worst_p = std::max(worst_p, (fk.X_FM.translation() - X.translation()).norm());
    worst_r = std::max(worst_r, RotationAngleBetween(fk.X_FM.linear(), X.linear()));
  }
  EXPECT_LE(worst_p, 1e-9);
  EXPECT_LE(worst_r, 1e-9);
}

TEST_F(RsrKinematicsTest, FastFeasibilityAgreesWithInverseKinematics) {
  std::mt19937 gen{7};
  std::uniform_real_distribution<double> scale(0.5, 1.5);
  int feasible = 0, infeasible = 0;
  for (int k = 0; k < 20000; ++k) {
    Eigen::Isometry3d X = RandomPose(gen);
    X.translation() = home_.translation() + scale(gen) * (X.translation() - home_.translation());
    const bool expected = CalcInverseKinematics(model_, X).feasible;
    EXPECT_EQ(IsPoseFeasible(model_, X), expected);
    (expected ? feasible : infeasible)++;
  }
  EXPECT_GT(feasible, 500);
  EXPECT_GT(infeasible, 500);
}

TEST_F(RsrKinematicsTest, FeasibilityAroundAPoseAgreesWithThePoseTest) {
  // A point cloud's poses (15 mm translations, 5° turns) around random poses, many across the boundary: the
  // precomputed legs give the verdict of IsPoseFeasible on the same pose.
  std::mt19937 gen{11};
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int feasible = 0, infeasible = 0;
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Isometry3d X = RandomPose(gen);
    const PoseFeasibilityAround around(model_, X);
    for (int j = 0; j < 10; ++j) {
      const Eigen::Vector3d offset = 0.015 * Eigen::Vector3d(u(gen), u(gen), u(gen));
      Eigen::Isometry3d X_t = X;
      X_t.translation() += offset;
      const bool expected = IsPoseFeasible(model_, X_t);
      EXPECT_EQ(around.Translated(offset), expected);
      const Eigen::Matrix3d R_step = RotationFromRpy(DegToRad(5) * Eigen::Vector3d(u(gen), u(gen), u(gen)));
      Eigen::Isometry3d X_r = X;
      X_r.linear() = R_step * X.linear();
      EXPECT_EQ(around.Rotated(R_step), IsPoseFeasible(model_, X_r));
      (expected ? feasible : infeasible)++;
    }
  }
  EXPECT_GT(feasible, 500);
  EXPECT_GT(infeasible, 500);
}

TEST_F(RsrKinematicsTest, JacobianMatchesCentralFiniteDifferencesOfIk) {
  std::mt19937 gen{3};
  const double h = 1e-6;
  for (int k = 0; k < 200; ++k) {
    const Eigen::Isometry3d X = RandomPose(gen);
    if (!CalcInverseKinematics(model_, X).feasible) continue;
    const Matrix6d J = CalcJacobian(model_, X);
    for (int c = 0; c < 6; ++c) {
      Vector6d twist = Vector6d::Zero();
      twist[c] = h;
      auto moved = [&](double sign) {
        Eigen::Isometry3d Y = X;
        Y.translation() += sign * twist.head<3>();
        Y.linear() = RotationFromVector(sign * twist.tail<3>()) * X.linear();
        return CalcInverseKinematics(model_, Y).joints.actuated();
      };
      const Vector6d fd = (moved(1) - moved(-1)) / (2 * h);
      EXPECT_LE((J.col(c) - fd).cwiseAbs().maxCoeff(), 1e-7) << "column " << c;
    }
  }
}

// The assumed geometry (README.md): at home a 517 N axial load is shared equally, 517/3 N per linear actuator, no rotary torque.
TEST_F(RsrKinematicsTest, AxialLoadAtHomeSharedEqually) {
  Vector6d wrench = Vector6d::Zero();
  wrench[2] = -517.0;
  const RsrStaticsResult s = CalcActuatorEfforts(model_, home_, wrench);
  ASSERT_FALSE(s.singular);
  for (int i = 0; i < kNumArms; ++i) {
    EXPECT_NEAR(s.linear_force_n[i], 517.0 / 3.0, 1e-9);
    EXPECT_NEAR(s.rotary_torque_nm[i], 0.0, 1e-9);
  }
}

// Statics is the dual of the Jacobian: the virtual work of the efforts equals that of the wrench they balance.
TEST_F(RsrKinematicsTest, StaticsIsPowerConsistentWithJacobian) {
  std::mt19937 gen{11};
  std::normal_distribution<double> n(0.0, 100.0);
  for (int k = 0; k < 100; ++k) {
    const Eigen::Isometry3d X = RandomPose(gen);
    Vector6d w, twist;
    for (int j = 0; j < 6; ++j) w[j] = n(gen), twist[j] = n(gen) * 1e-3;
    const RsrStaticsResult s = CalcActuatorEfforts(model_, X, w);
    Vector6d Q;
    Q << s.rotary_torque_nm, s.linear_force_n;
    EXPECT_NEAR(Q.dot(CalcJacobian(model_, X) * twist), -w.dot(twist), 1e-6 * (1 + std::abs(w.dot(twist))));
  }
}

// The default geometry has 3-fold symmetry about the robot axis: conjugating the pose by a 120 deg turn about z,
// Y = Rz X Rz^-1, permutes the arms.
TEST_F(RsrKinematicsTest, ThreeFoldSymmetryAboutTheAxis) {
  std::mt19937 gen{5};
  const Eigen::Matrix3d Rz120 = Eigen::AngleAxisd(DegToRad(120), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (int k = 0; k < 500; ++k) {
    const Eigen::Isometry3d X = RandomPose(gen);
    Eigen::Isometry3d Y = X;
    Y.translation() = Rz120 * X.translation();
    Y.linear() = Rz120 * X.linear() * Rz120.transpose();
    const RsrIkResult a = CalcInverseKinematics(model_, X);
    const RsrIkResult b = CalcInverseKinematics(model_, Y);
    // Arm angles -30, 90, 210: rotating by +120 deg maps arm 1 -> 2, 2 -> 3, 3 -> 1.
    for (int i = 0; i < kNumArms; ++i) {
      const int j = (i + 1) % kNumArms;
      EXPECT_NEAR(a.joints.d_m[i], b.joints.d_m[j], 1e-12);
      EXPECT_NEAR(a.joints.theta_rad[i], b.joints.theta_rad[j], 1e-10);
      EXPECT_NEAR(a.joints.psi_rad[i], b.joints.psi_rad[j], 1e-10);
    }
    EXPECT_EQ(a.feasible, b.feasible);
  }
}

TEST_F(RsrKinematicsTest, LimitVerdictNamesTheViolatedJoint) {
  Eigen::Isometry3d X = home_;
  X.translation().z() += 0.10;  // all strokes beyond 354 mm
  const RsrIkResult ik = CalcInverseKinematics(model_, X);
  EXPECT_FALSE(ik.feasible);
  const RsrLimitCheck& worst = ik.tightest();
  EXPECT_EQ(worst.joint, RsrJointKind::kStroke);
  EXPECT_DOUBLE_EQ(worst.limit, 0.354);
  EXPECT_NEAR(worst.margin, 0.354 - 0.384, 1e-12);
}

TEST_F(RsrKinematicsTest, ForwardKinematicsReportsFailureForUnassemblableJoints) {
  RsrJointVector q;
  q << 0, 0, 0, 0.01, 0.9, 0.01;  // no pose has these leg lengths
  const RsrFkResult fk = CalcForwardKinematics(model_, q, home_);
  EXPECT_FALSE(fk.converged());
  RsrJointVector bad = RsrJointVector::Constant(std::nan(""));
  EXPECT_FALSE(CalcForwardKinematics(model_, bad, home_).converged());
}

TEST_F(RsrKinematicsTest, KinematicsAllocateNothing) {
  std::mt19937 gen{1};
  const Eigen::Isometry3d X = RandomPose(gen);
  const RsrJointVector q = CalcInverseKinematics(model_, X).joints.actuated();
  testing::AllocationCounter counter;
  const RsrIkResult ik = CalcInverseKinematics(model_, X);
  const bool ok = IsPoseFeasible(model_, X);
  const Matrix6d J = CalcJacobian(model_, X);
  const RsrFkResult fk = CalcForwardKinematics(model_, q, home_);
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_EQ(ok, ik.feasible);
  EXPECT_TRUE(J.allFinite());
  EXPECT_TRUE(fk.converged());
}

}  // namespace
}  // namespace robossis::robot
