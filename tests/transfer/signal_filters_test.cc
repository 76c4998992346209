// Up-sampling, moving average, Kalman filter (eq. 12) and cap guard.

#include <random>

#include <Eigen/Eigenvalues>

#include <gtest/gtest.h>

#include "haptics/transfer/signal_filters.h"

namespace robossis::transfer {
namespace {

TEST(LinearUpsamplerTest, InterpolatesLinearlyBetweenSlowTargets) {
  LinearUpsampler up(10, Vector6d::Zero());
  up.SetTarget(Vector6d::Constant(1.0));
  for (int j = 1; j <= 10; ++j) EXPECT_NEAR(up.Next()[0], j / 10.0, 1e-15);
  EXPECT_DOUBLE_EQ(up.Next()[0], 1.0);  // no new target: hold
}

TEST(MovingAverageTest, AveragesTheWindow) {
  MovingAverage ma(4, Vector6d::Zero());
  Vector6d out;
  for (int k = 1; k <= 4; ++k) out = ma.Step(Vector6d::Constant(k));
  EXPECT_DOUBLE_EQ(out[3], 2.5);
}

TEST(KalmanCaTest, CovarianceStaysSymmetricPositiveDefinite) {
  std::mt19937 gen{42};
  std::normal_distribution<double> noise(0.0, 1e-3);
  KalmanCa kf(1e-4, 1e-5, 1e-4, Vector6d::Zero());
  for (int k = 0; k < 20000; ++k) {
    if (k % 97 == 0) {
      kf.Predict();
    } else {
      Vector6d z;
      for (int i = 0; i < 6; ++i) z[i] = 0.01 * std::sin(k * 1e-3 * (i + 1)) + noise(gen);
      kf.Step(z);
    }
    const Eigen::Matrix3d& P = kf.covariance();
    ASSERT_LE((P - P.transpose()).cwiseAbs().maxCoeff(), 1e-15 * P.cwiseAbs().maxCoeff());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(P);
    ASSERT_GT(eig.eigenvalues().minCoeff(), 0.0) << "step " << k;
  }
}

TEST(KalmanCaTest, TracksConstantAccelerationWithoutBias) {
  // The constant-acceleration model follows a parabola exactly in steady state (a type-3 tracker).
  const double dt = 1e-4;
  KalmanCa kf(dt, 1e-5, 1e-4, Vector6d::Zero());
  const double a = 0.02;
  for (int k = 1; k <= 50000; ++k) {
    const double t = k * dt;
    kf.Step(Vector6d::Constant(0.5 * a * t * t));
  }
  const double t = 50000 * dt;
  EXPECT_NEAR(kf.state()(0, 0), 0.5 * a * t * t, 1e-9);
  EXPECT_NEAR(kf.state()(1, 0), a * t, 1e-6);
  EXPECT_NEAR(kf.state()(2, 0), a, 1e-4);
}

TEST(KalmanCaTest, ResetIsAFreshFilterAtThePosition) {
  const Vector6d b = Vector6d::Constant(0.003);
  KalmanCa used(1e-4, 1e-5, 1e-4, Vector6d::Zero());
  for (int i = 0; i < 500; ++i) used.Step(Vector6d::Constant(1e-6 * i));
  used.Reset(b);
  KalmanCa fresh(1e-4, 1e-5, 1e-4, b);
  for (int i = 0; i < 50; ++i) {
    used.Step(b + Vector6d::Constant(1e-6 * i));
    fresh.Step(b + Vector6d::Constant(1e-6 * i));
  }
  EXPECT_LT((used.state() - fresh.state()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((used.covariance() - fresh.covariance()).cwiseAbs().maxCoeff(), 1e-20);
}

TEST(CapGuardTest, NeverExceedsTheCapsOnTheNorm) {
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SpeedCaps caps;
  CapGuard guard(1e-4, caps, 60, 0.003, Vector6d::Zero());
  for (int k = 0; k < 20000; ++k) {
    Vector6d p, v;
    for (int i = 0; i < 6; ++i) {
      p[i] = 0.1 * u(gen);
      v[i] = 1.0 * u(gen);  // wildly beyond the caps
    }
    guard.Step(p, v);
    ASSERT_LE(guard.velocity().head<3>().norm(), caps.max_linear_speed_m_s);
    ASSERT_LE(guard.velocity().tail<3>().norm(), caps.max_angular_speed_rad_s);
    ASSERT_LE(guard.last_increment().head<3>().norm(), caps.max_linear_speed_m_s * 1e-4);
  }
}

TEST(CapGuardTest, ConvergesToTheReference) {
  CapGuard guard(1e-4, SpeedCaps{}, 60, 0.003, Vector6d::Zero());
  const Vector6d target = (Vector6d() << 0.002, -0.001, 0.0005, 0.001, 0, -0.002).finished();
  for (int k = 0; k < 30000; ++k) guard.Step(target, Vector6d::Zero());
  EXPECT_LT((guard.position() - target).norm(), 1e-9);
}

}  // namespace
}  // namespace robossis::transfer
