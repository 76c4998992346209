// The one fit of the transforms and the tracker's clock (calibration/clock_fit.h): its continuous-time reference,
// its analytic Jacobian, and what it reports on single synthetic takes (the many-seed acceptance is
// clock_acceptance_test.cc).

#include "calibration/clock_fit.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "calibration/reference_curve.h"
#include "calibration/tracking_eval.h"
#include "calibration/tracking_report.h"
#include "tests/calibration/test_support.h"

namespace robossis::calibration {
namespace {

using ::testing::HasSubstr;

// Catmull-Rom tangents reproduce a quadratic exactly on a uniform grid: position and velocity between samples.
TEST(ReferenceCurveTest, ReproducesAQuadraticAndItsVelocity) {
  PoseTrajectory traj;
  auto p = [](double t) { return Eigen::Vector3d(0.01 * t * t, -0.02 * t + 0.003 * t * t, 0.1); };
  for (int i = 0; i <= 100; ++i) traj.Add(i * 0.01, p(i * 0.01), Eigen::Quaterniond::Identity());
  const ReferenceCurve curve(traj);
  ReferenceState s;
  for (double t : {0.0123, 0.5, 0.777, 0.989}) {
    ASSERT_TRUE(curve.Evaluate(t, s));
    if (t > 0.02 && t < 0.98) {  // one-sided tangents at the ends
      EXPECT_LT((s.p_FM - p(t)).norm(), 1e-12) << t;
      EXPECT_LT((s.v_FM - Eigen::Vector3d(0.02 * t, -0.02 + 0.006 * t, 0)).norm(), 1e-10) << t;
    }
  }
  EXPECT_FALSE(curve.Evaluate(1.0001, s));
  EXPECT_FALSE(curve.Evaluate(-0.0001, s));
}

TEST(ReferenceCurveTest, AngularVelocityOfAConstantRotation) {
  PoseTrajectory traj;
  for (int i = 0; i <= 50; ++i) {
    traj.Add(i * 0.01, Eigen::Vector3d::Zero(), Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * i * 0.01,
                                                                                     Eigen::Vector3d::UnitZ())));
  }
  const ReferenceCurve curve(traj);
  ReferenceState s;
  ASSERT_TRUE(curve.Evaluate(0.2345, s));
  EXPECT_LT((s.w_FM - Eigen::Vector3d(0, 0, 0.3)).norm(), 1e-9);
  EXPECT_LT(RotationAngleBetween(s.R_FM, Eigen::AngleAxisd(0.3 * 0.2345, Eigen::Vector3d::UnitZ()).matrix()), 1e-9);
}

// The analytic Jacobian against central differences, at a pose with a residual of the tracker's size.
TEST(ClockFitJacobianTest, MatchesFiniteDifferences) {
  const PoseTrajectory motion = testing::BenchMotion(3, 10.0, 1000.0, 0.010, 3.0);
  const ReferenceCurve curve(motion);
  ClockFitParameters x;
  x.X_FT = PoseFromMmDeg((Vector6d() << 350, -420, 1650, 178, -3, 35).finished()).inverse();
  x.X_MB = PoseFromMmDeg((Vector6d() << 12, -8, 30, 2, -1, 40).finished());
  x.offset_mid_s = 0.0123;
  x.drift = 20e-6;
  const double t_mid = 5.0;
  constexpr int kDriftColumn = 13;
  for (double t : {2.3, 4.71, 7.9}) {
    ReferenceState s;
    ASSERT_TRUE(curve.Evaluate(t + x.offset_mid_s + x.drift * (t - t_mid), s));
    Eigen::Isometry3d X_FM = Eigen::Isometry3d::Identity();
    X_FM.linear() = RotationFromVector(Eigen::Vector3d(1e-4, -2e-4, 1e-4)) * s.R_FM;
    X_FM.translation() = s.p_FM + Eigen::Vector3d(1e-4, 0, -1e-4);
    const Eigen::Isometry3d X_TB = x.X_FT.inverse() * X_FM * x.X_MB;  // the tracked pose, slightly off
    Eigen::Matrix<double, 6, 1> r, rp, rm;
    Eigen::Matrix<double, 6, 14> J;
    ASSERT_TRUE(ClockFitResidual(curve, x, t_mid, t, X_TB, r, &J));
    for (int k = 0; k < 14; ++k) {
      const double h = k == kDriftColumn ? 1e-8 : 1e-6;  // the drift multiplies seconds
      Eigen::Matrix<double, 14, 1> d = Eigen::Matrix<double, 14, 1>::Zero();
      d[k] = h;
      ASSERT_TRUE(ClockFitResidual(curve, PerturbClockFitParameters(x, d), t_mid, t, X_TB, rp, nullptr));
      ASSERT_TRUE(ClockFitResidual(curve, PerturbClockFitParameters(x, -d), t_mid, t, X_TB, rm, nullptr));
      const Eigen::Matrix<double, 6, 1> numeric = (rp - rm) / (2 * h);
      // First order in the residual rotation (~2e-4 rad): agreement to a few 1e-4 of the column's size.
      EXPECT_LT((J.col(k) - numeric).norm(), 1e-3 * std::max(1.0, numeric.norm())) << "t " << t << " column " << k;
    }
  }
}

struct Take {
  SyntheticTrackerOptions tracker;
  PoseTrajectory commanded;
  TrackingEvalResult result;
};

// 90 s at 240 Hz, 0.1 mm noise, 6 occlusions: the acceptance's take.
Take RunTake(std::uint32_t seed, double offset_s, double drift, const PoseTrajectory* motion = nullptr) {
  Take take;
  take.commanded = motion ? *motion : testing::BenchMotion(seed, 90.0, 1000.0, 0.010, 3.0);
  take.tracker = testing::ClockTakeTracker(seed, offset_s, drift);
  MotiveReader reader(testing::WriteTake(take.commanded, take.tracker), "take.csv");
  const RigidBodyTrack track = ReadRigidBodyTrack(reader, take.tracker.rigid_body_name);
  take.result = EvaluateTracking(track, take.commanded);
  return take;
}

double TrueOffsetAtMid(const Take& t) {
  return t.tracker.clock_offset_s + t.tracker.clock_drift * t.result.clock_fit.t_mid_s;
}

TEST(ClockFitTest, RecoversTheOffsetNearTheBoundOnA90sTake) {
  const Take t = RunTake(7, 0.0123, 0.0);
  const ClockFitResult& c = t.result.clock_fit;
  EXPECT_FALSE(c.drift_selected);
  EXPECT_TRUE(c.identifiable) << c.warning;
  // Within 4 standard deviations (the fit is near the bound: its curvature sigma within 10 % of the bound).
  EXPECT_LT(std::abs(c.offset_mid_s - TrueOffsetAtMid(t)), 4 * c.offset_sigma_curvature_s);
  EXPECT_LT(c.offset_sigma_curvature_s, 1.1 * c.crb_s);
  EXPECT_LT(c.offset_ci_s[0], TrueOffsetAtMid(t));
  EXPECT_GT(c.offset_ci_s[1], TrueOffsetAtMid(t));
  EXPECT_LT(c.drift_bound, 10e-6);  // "no drift", bounded to a few ppm on 90 s
  EXPECT_NEAR(c.sigma_position_m, 0.1e-3, 0.01e-3);  // the truncated Gaussian's σ: bound/3, slightly less
}

TEST(ClockFitTest, SelectsDriftWhereTheDataAsksForIt) {
  const Take t = RunTake(8, -0.0171, 50e-6);
  const ClockFitResult& c = t.result.clock_fit;
  EXPECT_TRUE(c.drift_selected);
  EXPECT_NEAR(c.drift, 50e-6, 10e-6);
  EXPECT_LT(std::abs(c.offset_mid_s - TrueOffsetAtMid(t)), 0.3e-3);
}

// --no-drift: the offset-only model, and no bound claimed for a drift that was not tested.
TEST(ClockFitTest, OffsetOnlyModelClaimsNoDriftBound) {
  const PoseTrajectory motion = testing::BenchMotion(12, 30.0, 1000.0, 0.010, 3.0);
  const SyntheticTrackerOptions o = testing::ClockTakeTracker(12, 0.003, 0.0);
  MotiveReader reader(testing::WriteTake(motion, o), "take.csv");
  TrackingEvalOptions options;
  options.clock_fit.allow_drift = false;
  const TrackingEvalResult r = EvaluateTracking(ReadRigidBodyTrack(reader, o.rigid_body_name), motion, options);
  const nlohmann::ordered_json j = TrackingSummaryJson(r);
  EXPECT_TRUE(j["clock_drift_bound_ppm"].is_null());
  EXPECT_EQ(j["clock_model"], "offset only (drift not estimated)");
  EXPECT_THAT(ClockReportText(r.clock_fit), HasSubstr("not estimated"));
}

TEST(ClockFitTest, SummaryJsonHasTheClockKeys) {
  const Take t = RunTake(9, 0.005, 0.0);
  const nlohmann::ordered_json j = TrackingSummaryJson(t.result);
  const ClockFitResult& c = t.result.clock_fit;
  EXPECT_DOUBLE_EQ(j["clock_offset_ms"].get<double>(), c.offset_mid_s * 1e3);
  ASSERT_EQ(j["clock_offset_ci_ms"].size(), 2u);
  EXPECT_DOUBLE_EQ(j["clock_offset_ci_ms"][0].get<double>(), c.offset_ci_s[0] * 1e3);
  EXPECT_DOUBLE_EQ(j["clock_offset_crb_ms"].get<double>(), c.crb_s * 1e3);
  EXPECT_TRUE(j["clock_drift_ppm"].is_null());
  EXPECT_GT(j["clock_drift_bound_ppm"].get<double>(), 0);
  EXPECT_EQ(j["clock_model"], "offset only (BIC: no drift)");
  EXPECT_EQ(j["clock"]["coverage_factor"], 2);
  EXPECT_EQ(j["clock"]["budget"].size(), 4u);
  // Both intervals beside the combined one: the block bootstrap's and the curvature's.
  EXPECT_NEAR(j["clock"]["interval_bootstrap_ms"][1].get<double>(),
              (c.offset_mid_s + 2 * c.offset_sigma_bootstrap_s) * 1e3, 1e-9);
  EXPECT_NEAR(j["clock"]["interval_curvature_ms"][0].get<double>(),
              (c.offset_mid_s - 2 * c.offset_sigma_curvature_s) * 1e3, 1e-9);
  EXPECT_THAT(ClockReportText(c), HasSubstr("no drift"));
}

// The ring turning at a constant rate about one axis (and so moving at a constant speed on a circle): an offset is
// a rotation of the tracker about that axis. A clear warning and the search window, not a confident number.
TEST(ClockFitTest, WarnsWhenTheMotionCannotFixTheOffset) {
  PoseTrajectory spin;
  for (int i = 0; i <= 60000; ++i) {
    const double t = i / 1000.0, a = 0.2 * t;
    spin.Add(t, Eigen::Vector3d(0.03 * std::cos(a), 0.03 * std::sin(a), 0.284),
             Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ())));
  }
  const Take t = RunTake(10, 0.004, 0.0, &spin);
  const ClockFitResult& c = t.result.clock_fit;
  EXPECT_FALSE(c.identifiable);
  EXPECT_THAT(c.warning, HasSubstr("does not fix the clock offset"));
  EXPECT_GE(c.offset_ci_s[1] - c.offset_ci_s[0], 2 * 2.0);
  EXPECT_THAT(ClockReportText(c), HasSubstr("warning:"));
}

TEST(ClockFitTest, WarnsWhenTheRingStandsStill) {
  PoseTrajectory still;
  for (int i = 0; i <= 3000; ++i) still.Add(i * 0.01, Eigen::Vector3d(0, 0, 0.284), Eigen::Quaterniond::Identity());
  const Take t = RunTake(11, 0.004, 0.0, &still);
  const ClockFitResult& c = t.result.clock_fit;
  EXPECT_FALSE(c.identifiable);
  EXPECT_THAT(c.warning, HasSubstr("does not fix the clock offset"));
  EXPECT_LE(c.offset_ci_s[0], -2.0 + c.offset_mid_s);
  EXPECT_GE(c.offset_ci_s[1], 2.0 + c.offset_mid_s);
}

}  // namespace
}  // namespace robossis::calibration
