#include "robot/feasible_motion.h"

#include <cmath>
#include <random>

#include <Eigen/QR>
#include <gtest/gtest.h>

#include "src/core/units.h"
#include "tests/support/alloc_counter.h"

namespace robossis::robot {
namespace {

// The QP against a case with a closed-form answer: the nearest point of a rotated box is Q^T clamp(Q y).
TEST(ProjectionQpTest, ProjectsOntoARotatedBox) {
  std::mt19937 gen{42};
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::Matrix<double, 6, 6> M;
    for (int i = 0; i < 36; ++i) M(i) = normal(gen);
    const Eigen::Matrix<double, 6, 6> Q = Eigen::HouseholderQR<Eigen::Matrix<double, 6, 6>>(M).householderQ();
    QpVector half;
    for (int i = 0; i < 6; ++i) half[i] = 0.1 + std::abs(normal(gen));
    ProjectionQp qp;
    qp.num_constraints = 12;
    qp.A.topRows<6>() = Q;  // Q y >= -half
    qp.A.middleRows<6>(6) = -Q;  // Q y <= half
    qp.b.head<6>() = -half;
    qp.b.segment<6>(6) = -half;
    QpVector target;
    for (int i = 0; i < 6; ++i) target[i] = 2.0 * normal(gen);
    const QpVector expected = Q.transpose() * (Q * target).cwiseMax(-half).cwiseMin(half);
    const QpResult r = SolveProjectionQp(qp, target, QpVector::Zero());
    ASSERT_EQ(r.status, QpStatus::kOptimal) << "trial " << trial;
    EXPECT_LT((r.y - expected).norm(), 1e-9) << "trial " << trial;
  }
}

TEST(ProjectionQpTest, RefusesAnInfeasibleStart) {
  ProjectionQp qp;
  qp.num_constraints = 1;
  qp.A(0, 0) = 1.0;
  qp.b[0] = 1.0;  // y0 >= 1, start at 0
  EXPECT_EQ(SolveProjectionQp(qp, QpVector::Zero(), QpVector::Zero()).status, QpStatus::kStartInfeasible);
}

class FeasibleMotionTest : public ::testing::Test {
 protected:
  const RsrModel model_ = RsrModel::Default();
  const Eigen::Isometry3d home_ = model_.geometry().X_FM_home;
  const FeasibleMotionGuard guard_{model_};

  Eigen::Isometry3d RandomFeasiblePose(std::mt19937& gen) const {
    std::uniform_real_distribution<double> pos(-0.1, 0.1), z(-0.06, 0.06), ang(-DegToRad(20), DegToRad(20));
    for (;;) {
      Eigen::Isometry3d X = home_;
      X.translation() += Eigen::Vector3d(pos(gen), pos(gen), z(gen));
      X.linear() = RotationFromRpy(Eigen::Vector3d(ang(gen), ang(gen), ang(gen)));
      if (CalcInverseKinematics(model_, X).feasible) return X;
    }
  }
  // A wanted pose far outside the workspace: +/-250 mm and +/-60 degrees around home.
  Eigen::Isometry3d RandomWildPose(std::mt19937& gen) const {
    std::uniform_real_distribution<double> pos(-0.25, 0.25), ang(-DegToRad(60), DegToRad(60));
    Eigen::Isometry3d X = home_;
    X.translation() += Eigen::Vector3d(pos(gen), pos(gen), pos(gen));
    X.linear() = RotationFromRpy(Eigen::Vector3d(ang(gen), ang(gen), ang(gen)));
    return X;
  }
};

// The gradients of the linearised limits against central differences of the margins.
TEST_F(FeasibleMotionTest, LinearisedLimitsMatchFiniteDifferences) {
  std::mt19937 gen{7};
  const FeasibleMotionConfig config;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Isometry3d X = RandomFeasiblePose(gen);
    const LinearizedLimits lin = CalcLinearizedLimits(model_, X, config);
    const double h = 1e-6;
    for (int j = 0; j < 6; ++j) {
      Vector6d step = Vector6d::Zero();
      step[j] = h;
      const LinearizedLimits plus = CalcLinearizedLimits(model_, ApplyTwistStep(X, step), config);
      const LinearizedLimits minus = CalcLinearizedLimits(model_, ApplyTwistStep(X, -step), config);
      for (int k = 0; k < kNumLinearizedLimits; ++k) {
        const double numeric = (plus.margin[k] - minus.margin[k]) / (2 * h);
        EXPECT_NEAR(lin.gradient(k, j), numeric, 1e-6 * (1.0 + std::abs(numeric))) << "limit " << k << " dir " << j;
      }
    }
  }
}

// The margins agree with the exact IK's verdict.
TEST_F(FeasibleMotionTest, MarginsAgreeWithTheExactIk) {
  std::mt19937 gen{8};
  for (int trial = 0; trial < 2000; ++trial) {
    const Eigen::Isometry3d X = RandomWildPose(gen);
    const LinearizedLimits lin = CalcLinearizedLimits(model_, X, FeasibleMotionConfig{});
    if (X.translation().z() < 0.15) continue;  // far below the ring plane the margins are not meaningful
    EXPECT_EQ(lin.margin.minCoeff() >= 0.0, CalcInverseKinematics(model_, X).feasible) << "trial " << trial;
  }
}

// Inside the workspace the step is the wanted one, exactly.
TEST_F(FeasibleMotionTest, InsideTheWorkspaceTheStepIsTheWantedOne) {
  std::mt19937 gen{9};
  std::uniform_real_distribution<double> small(-1e-4, 1e-4);
  int tracked = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const Eigen::Isometry3d X = RandomFeasiblePose(gen);
    if (CalcInverseKinematics(model_, X).tightest().margin < 2e-3) continue;  // well inside only
    Vector6d step;
    for (int i = 0; i < 6; ++i) step[i] = small(gen);
    const Eigen::Isometry3d wanted = ApplyTwistStep(X, step);
    const FeasibleMotionResult r = guard_.Step(X, wanted);
    ASSERT_EQ(r.status, FeasibleMotionStatus::kTracked) << "trial " << trial;
    EXPECT_TRUE(r.X_FM.matrix() == wanted.matrix());
    ++tracked;
  }
  EXPECT_GT(tracked, 100);
}

// Random and adversarial wanted poses (far outside, +/-60 degrees, jumps across the workspace) never give an
// infeasible pose, over long chains of steps.
TEST_F(FeasibleMotionTest, NeverReturnsAnInfeasiblePose) {
  std::mt19937 gen{10};
  Eigen::Isometry3d X = home_;
  int constrained = 0;
  for (int step = 0; step < 20000; ++step) {
    const Eigen::Isometry3d wanted = (step % 50 == 0 || step % 7 == 3) ? RandomWildPose(gen) : RandomFeasiblePose(gen);
    const FeasibleMotionResult r = guard_.Step(X, wanted);
    ASSERT_TRUE(CalcInverseKinematics(model_, r.X_FM).feasible) << "step " << step << " " << ToString(r.status);
    ASSERT_NE(r.status, FeasibleMotionStatus::kStartInfeasible);
    constrained += r.status != FeasibleMotionStatus::kTracked;
    X = r.X_FM;
  }
  EXPECT_GT(constrained, 100);  // the adversarial targets did reach the walls
}

// A fast hand (250 mm/s and 60 deg/s at 10 kHz) heading far outside: every pose on the way is feasible, and the
// guard ends at the wall instead of holding far from it.
TEST_F(FeasibleMotionTest, FastMotionFarOutsideStopsAtTheWall) {
  std::mt19937 gen{11};
  for (int trial = 0; trial < 6; ++trial) {
    const Eigen::Isometry3d target = RandomWildPose(gen);
    Eigen::Isometry3d X = home_;
    const double dt = 1e-4;
    for (int tick = 0; tick < 8000; ++tick) {  // 0.8 s: up to 200 mm and 48 deg
      Vector6d towards = TwistStepBetween(X, target);
      const double lin = towards.head<3>().norm(), ang = towards.tail<3>().norm();
      const double s = std::min({1.0, 0.25 * dt / std::max(lin, 1e-12), DegToRad(60) * dt / std::max(ang, 1e-12)});
      const FeasibleMotionResult r = guard_.Step(X, ApplyTwistStep(X, s * towards));
      ASSERT_TRUE(CalcInverseKinematics(model_, r.X_FM).feasible) << "trial " << trial << " tick " << tick;
      X = r.X_FM;
    }
    if (!CalcInverseKinematics(model_, target).feasible) {
      EXPECT_LT(CalcInverseKinematics(model_, X).tightest().margin, 1e-3) << "trial " << trial;
    }
  }
}

// A pop-through: from just inside a wall the wanted pose jumps to the far side of the workspace's boundary.
TEST_F(FeasibleMotionTest, PopThroughIsRefused) {
  Eigen::Isometry3d X = home_;
  Eigen::Isometry3d wanted = home_;
  wanted.translation().z() += 0.2;  // every stroke past its maximum
  for (int i = 0; i < 200; ++i) X = guard_.Step(X, wanted).X_FM;
  const double stroke_max = model_.limits().stroke_max_m;
  EXPECT_NEAR(CalcInverseKinematics(model_, X).joints.d_m.maxCoeff(), stroke_max, 1e-5);
  const FeasibleMotionResult r = guard_.Step(X, wanted);
  EXPECT_TRUE(CalcInverseKinematics(model_, r.X_FM).feasible);
  EXPECT_LE(CalcInverseKinematics(model_, r.X_FM).joints.d_m.maxCoeff(), stroke_max);
}

// At a wall the motion slides along it: the tangential part of the wanted step is kept, the outward part dropped.
TEST_F(FeasibleMotionTest, AtAWallTheMotionSlidesAlongIt) {
  // Drive up into the maximum strokes (all three legs at once). There, lateral motion and yaw are tangential
  // (first order: d_dot_i = n_i · v with n_i = z, and (e_i × z) · omega = 0 for a pure yaw).
  Eigen::Isometry3d X = home_;
  Eigen::Isometry3d wanted = home_;
  wanted.translation().z() += 0.3;
  for (int i = 0; i < 100; ++i) X = guard_.Step(X, wanted).X_FM;
  ASSERT_NEAR(CalcInverseKinematics(model_, X).joints.d_m.maxCoeff(), model_.limits().stroke_max_m, 1e-5);
  for (int i = 0; i < 200; ++i) {
    Vector6d step = Vector6d::Zero();
    step[0] = 1e-6;           // 1 µm sideways: tangential
    step[2] = 2e-6;           // 2 µm up: outward
    step[5] = DegToRad(1e-4); // yaw: tangential
    const Eigen::Isometry3d before = X;
    const FeasibleMotionResult r = guard_.Step(X, ApplyTwistStep(X, step));
    ASSERT_TRUE(CalcInverseKinematics(model_, r.X_FM).feasible);
    EXPECT_EQ(r.status, FeasibleMotionStatus::kConstrained) << "tick " << i;
    X = r.X_FM;
    const Vector6d moved = TwistStepBetween(before, X);
    EXPECT_NEAR(moved[0], step[0], 0.02e-6) << "tick " << i;  // the tangential motion is kept
    EXPECT_NEAR(moved[5], step[5], 0.02 * step[5]) << "tick " << i;
    EXPECT_LT(moved[2], 1e-9) << "tick " << i;                // the outward motion is dropped
  }
  EXPECT_NEAR(X.translation().x(), 200e-6, 5e-6);  // it slid 0.2 mm along the wall
}

TEST_F(FeasibleMotionTest, NonFiniteWantedPoseHolds) {
  Eigen::Isometry3d wanted = home_;
  wanted.translation().x() = std::nan("");
  const FeasibleMotionResult r = guard_.Step(home_, wanted);
  EXPECT_EQ(r.status, FeasibleMotionStatus::kInvalidInput);
  EXPECT_TRUE(r.X_FM.matrix() == home_.matrix());
}

TEST_F(FeasibleMotionTest, InfeasibleStartIsReportedAndNotMoved) {
  Eigen::Isometry3d X = home_;
  X.translation().z() += 0.2;
  const FeasibleMotionResult r = guard_.Step(X, home_);
  EXPECT_EQ(r.status, FeasibleMotionStatus::kStartInfeasible);
  EXPECT_TRUE(r.X_FM.matrix() == X.matrix());
}

TEST_F(FeasibleMotionTest, StepAllocatesNothing) {
  std::mt19937 gen{12};
  std::vector<Eigen::Isometry3d> wanted;
  for (int i = 0; i < 200; ++i) wanted.push_back(i % 2 ? RandomWildPose(gen) : RandomFeasiblePose(gen));
  Eigen::Isometry3d X = home_;
  testing::AllocationCounter counter;
  for (const Eigen::Isometry3d& w : wanted) X = guard_.Step(X, w).X_FM;
  EXPECT_EQ(counter.count(), 0u);
}

TEST(FeasibleMotionConfigTest, RejectsBadValuesNamingTheField) {
  FeasibleMotionConfig config;
  config.approach_gain = 0;
  try {
    config.Validate();
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("approach_gain"), std::string::npos);
  }
}

}  // namespace
}  // namespace robossis::robot
