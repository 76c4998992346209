#include "calibration/registration.h"

#include <random>

#include <gtest/gtest.h>

#include "src/core/pose.h"
#include "src/core/units.h"
#include "tests/calibration/test_support.h"

namespace robossis::calibration {
namespace {

TEST(RegistrationTest, RigidFitRecoversTransformExactly) {
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  const Eigen::Isometry3d X = PoseFromMmDeg((Vector6d() << 120, -40, 800, 20, -35, 170).finished());
  std::vector<Eigen::Vector3d> a, b;
  for (int i = 0; i < 6; ++i) {
    a.emplace_back(u(gen), u(gen), u(gen));
    b.push_back(X * a.back());
  }
  const RigidFit fit = FitRigidTransform(a, b);
  EXPECT_TRUE(fit.X.isApprox(X, 1e-12));
  EXPECT_LT(fit.rms_m, 1e-12);
}

TEST(RegistrationTest, RigidFitNeedsThreePoints) {
  EXPECT_THROW(FitRigidTransform({Eigen::Vector3d::Zero()}, {Eigen::Vector3d::Zero()}), std::invalid_argument);
}

struct HandEyeCase {
  Eigen::Isometry3d X_FT, X_MB;
  std::vector<Eigen::Isometry3d> X_FM, X_TB;
};

HandEyeCase MakeCase(double pos_noise_m, double rot_noise_rad) {
  std::mt19937 gen{42};
  std::normal_distribution<double> n(0, 1);
  HandEyeCase c;
  c.X_FT = PoseFromMmDeg((Vector6d() << -300, 450, 1600, 176, 4, -60).finished());
  c.X_MB = PoseFromMmDeg((Vector6d() << 15, -10, 35, 3, -2, 25).finished());
  const PoseTrajectory motion = testing::TestMotion(30.0, 50.0);
  for (std::size_t i = 0; i < motion.size(); ++i) {
    const Eigen::Isometry3d X_FM = motion.Pose(i);
    Eigen::Isometry3d X_TB = c.X_FT.inverse() * X_FM * c.X_MB;
    X_TB.translation() += pos_noise_m * Eigen::Vector3d(n(gen), n(gen), n(gen));
    X_TB.linear() = RotationFromVector(rot_noise_rad * Eigen::Vector3d(n(gen), n(gen), n(gen))) * X_TB.linear();
    c.X_FM.push_back(X_FM);
    c.X_TB.push_back(X_TB);
  }
  return c;
}

TEST(RegistrationTest, HandEyeRecoversTransformsWithoutNoise) {
  const HandEyeCase c = MakeCase(0, 0);
  const HandEyeResult r = CalibrateTrackerToBase(c.X_FM, c.X_TB);
  EXPECT_LT((r.X_FT.translation() - c.X_FT.translation()).norm(), 1e-9);
  EXPECT_LT(RotationAngleBetween(r.X_FT.linear(), c.X_FT.linear()), 1e-10);
  EXPECT_LT((r.X_MB.translation() - c.X_MB.translation()).norm(), 1e-9);
  EXPECT_LT(r.rms_position_m, 1e-9);
  EXPECT_EQ(r.method.rfind("robot-world-hand-eye", 0), 0u);
}

TEST(RegistrationTest, HandEyeWithFlex13NoiseWithinIssueTolerance) {
  // Goal: a known transform within 0.05 mm and 0.01°. Noise σ = 0.08/3 mm and 0.03/3° (the synthetic tracker's).
  const HandEyeCase c = MakeCase(0.08e-3 / 3, DegToRad(0.03) / 3);
  const HandEyeResult r = CalibrateTrackerToBase(c.X_FM, c.X_TB);
  // The translation is judged where it is used: the ring's workspace (home, 284 mm above the base), not the
  // tracker's origin 1.6 m away, where a 0.006° rotation error alone moves it by 0.17 mm.
  const Eigen::Vector3d p_F_home(0, 0, 0.284);
  const Eigen::Vector3d p_T = c.X_FT.inverse() * p_F_home;
  EXPECT_LT((r.X_FT * p_T - p_F_home).norm(), 0.05e-3);
  EXPECT_LT(RotationAngleBetween(r.X_FT.linear(), c.X_FT.linear()), DegToRad(0.01));
  EXPECT_LT((r.X_MB.translation() - c.X_MB.translation()).norm(), 0.05e-3);
  EXPECT_LT(RotationAngleBetween(r.X_MB.linear(), c.X_MB.linear()), DegToRad(0.01));
  EXPECT_NEAR(r.rms_position_m, std::sqrt(3.0) * 0.08e-3 / 3, 0.01e-3);  // residual = the noise, not more
}

TEST(RegistrationTest, TranslationOnlyMotionFallsBackToPositionFit) {
  HandEyeCase c = MakeCase(0, 0);
  for (std::size_t i = 0; i < c.X_FM.size(); ++i) {
    c.X_FM[i].linear().setIdentity();
    c.X_TB[i] = c.X_FT.inverse() * c.X_FM[i] * c.X_MB;
  }
  const HandEyeResult r = CalibrateTrackerToBase(c.X_FM, c.X_TB);
  EXPECT_EQ(r.method.rfind("rigid fit of positions", 0), 0u);
  EXPECT_LT(r.rms_position_m, 1e-9);  // predictions still exact: the offset is absorbed, not lost
  EXPECT_LT(RotationAngleBetween(r.X_FT.linear(), c.X_FT.linear()), 1e-9);
}

}  // namespace
}  // namespace robossis::calibration
