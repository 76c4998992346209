// The one hand-to-set-point delay estimator, on signals whose delay is known by construction.
#include "src/teleop/delay_estimate.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace robossis::teleop {
namespace {

// A smooth displacement (m, rad) with several frequencies, so that a single lag aligns it; at rest at t = 0 (as
// the delayed copy is before its delay).
Vector6d Motion(double t, bool linear, bool angular) {
  Vector6d x = Vector6d::Zero();
  const double s = 0.004 * (1 - std::cos(2.1 * t)) + 0.0015 * (1 - std::cos(5.3 * t)) + 0.001 * t * t;
  if (linear) x.head<3>() = Eigen::Vector3d(s, 0.5 * s, -0.2 * s);
  if (angular) x.tail<3>() = Eigen::Vector3d(0.3 * s, -s, 0.1 * s) * 5.0;
  return x;
}

struct Series {
  std::vector<double> t;
  std::vector<Vector6d> x;
};

// `rate_hz` samples over `duration_s` of Motion(t - delay) + offset.
Series Sample(double rate_hz, double duration_s, double delay_s, bool linear, bool angular,
              const Vector6d& offset = Vector6d::Zero()) {
  Series s;
  const int n = static_cast<int>(std::lround(duration_s * rate_hz));
  for (int k = 0; k <= n; ++k) {
    const double t = k / rate_hz;
    s.t.push_back(t);
    s.x.push_back((t < delay_s ? Motion(0, linear, angular) : Motion(t - delay_s, linear, angular)) + offset);
  }
  return s;
}

TEST(DelayEstimate, FindsAKnownDelayOfALinearMotion) {
  const Series ref = Sample(1000, 4.0, 0.0, true, false);
  for (double delay : {0.0, 0.0125, 0.037, 0.210}) {
    const Series out = Sample(1000, 4.0, delay, true, false);
    const DelayEstimate e = EstimateDelay(ref.t, ref.x, out.t, VelocityOf(out.t, out.x));
    ASSERT_TRUE(e.valid);
    EXPECT_FALSE(e.angular);
    EXPECT_NEAR(e.delay_s, delay, 0.5e-3) << "delay " << delay;
    EXPECT_LT(e.rms_residual, 1e-4);
  }
}

TEST(DelayEstimate, ComparesTheAngularPartWhenTheReferenceOnlyTurns) {
  const Series ref = Sample(1000, 4.0, 0.0, false, true);
  const Series out = Sample(1000, 4.0, 0.024, false, true);
  const DelayEstimate e = EstimateDelay(ref.t, ref.x, out.t, VelocityOf(out.t, out.x));
  ASSERT_TRUE(e.valid);
  EXPECT_TRUE(e.angular);
  EXPECT_NEAR(e.delay_s, 0.024, 0.5e-3);
}

TEST(DelayEstimate, AnOffsetFromADiscardedStallDoesNotBiasTheLag) {
  const Series ref = Sample(1000, 4.0, 0.0, true, false);
  Vector6d offset = Vector6d::Zero();
  offset.head<3>() = Eigen::Vector3d(0.003, -0.001, 0.002);
  const Series out = Sample(1000, 4.0, 0.042, true, false, offset);
  const DelayEstimate e = EstimateDelay(ref.t, ref.x, out.t, VelocityOf(out.t, out.x));
  ASSERT_TRUE(e.valid);
  EXPECT_NEAR(e.delay_s, 0.042, 0.5e-3);
}

TEST(DelayEstimate, ADelayedSeriesAtAnotherRateIsInterpolated) {
  // The off-line chain's case: a 1 kHz reference against a 10 kHz set-point subsampled at 2 kHz.
  const Series ref = Sample(1000, 3.0, 0.0, true, false);
  const Series out = Sample(2000, 3.0, 0.0335, true, false);
  const DelayEstimate e = EstimateDelay(ref.t, ref.x, out.t, VelocityOf(out.t, out.x));
  ASSERT_TRUE(e.valid);
  EXPECT_NEAR(e.delay_s, 0.0335, 0.5e-3);
}

TEST(DelayEstimate, TooFewSamplesGiveNoEstimate) {
  const Series ref = Sample(1000, 0.005, 0.0, true, false);
  const DelayEstimate e = EstimateDelay(ref.t, ref.x, ref.t, VelocityOf(ref.t, ref.x));
  EXPECT_FALSE(e.valid);
}

TEST(DelayEstimate, VelocityOfIsTheCentralDifference) {
  const std::vector<double> t = {0.0, 0.1, 0.3};
  std::vector<Vector6d> x(3, Vector6d::Zero());
  x[1][0] = 1.0;
  x[2][0] = 3.0;
  const std::vector<Vector6d> v = VelocityOf(t, x);
  EXPECT_DOUBLE_EQ(v[0][0], 10.0);
  EXPECT_DOUBLE_EQ(v[1][0], 10.0);
  EXPECT_DOUBLE_EQ(v[2][0], 10.0);
}

}  // namespace
}  // namespace robossis::teleop
