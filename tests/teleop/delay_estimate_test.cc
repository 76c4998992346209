// The hand-to-set-point delay (the one lag estimator, with the transfer's resets and the cap respected), on
// signals whose delay is known by construction.
#include "src/teleop/delay_estimate.h"

#include <algorithm>
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

DelayEstimate Estimate(const Series& ref, const Series& out, const DelaySearch& search = {}) {
  return EstimateDelay({.t_s = ref.t, .x = ref.x}, {.t_s = out.t, .x = out.x}, search);
}

TEST(DelayEstimate, FindsAKnownDelayOfALinearMotion) {
  const Series ref = Sample(1000, 4.0, 0.0, true, false);
  for (double delay : {0.0125, 0.037, 0.210}) {
    const Series out = Sample(1000, 4.0, delay, true, false);
    const DelayEstimate e = Estimate(ref, out);
    ASSERT_TRUE(e.ok()) << ToString(e.status);
    EXPECT_FALSE(e.angular);
    EXPECT_NEAR(e.delay_s, delay, 0.5e-3) << "delay " << delay;
    EXPECT_LT(e.rms_residual, 1e-4);
    EXPECT_GT(e.judged_fraction(), 0.8);
  }
}

TEST(DelayEstimate, ComparesTheAngularPartWhenTheReferenceOnlyTurns) {
  const Series ref = Sample(1000, 4.0, 0.0, false, true);
  const Series out = Sample(1000, 4.0, 0.024, false, true);
  const DelayEstimate e = Estimate(ref, out);
  ASSERT_TRUE(e.ok());
  EXPECT_TRUE(e.angular);
  EXPECT_NEAR(e.delay_s, 0.024, 0.5e-3);
}

TEST(DelayEstimate, AnOffsetFromADiscardedStallDoesNotBiasTheLag) {
  const Series ref = Sample(1000, 4.0, 0.0, true, false);
  Vector6d offset = Vector6d::Zero();
  offset.head<3>() = Eigen::Vector3d(0.003, -0.001, 0.002);
  const Series out = Sample(1000, 4.0, 0.042, true, false, offset);
  const DelayEstimate e = Estimate(ref, out);
  ASSERT_TRUE(e.ok());
  EXPECT_NEAR(e.delay_s, 0.042, 0.5e-3);
}

TEST(DelayEstimate, ADelayedSeriesAtAnotherRateIsInterpolated) {
  // The off-line chain's case: a 1 kHz reference against a 10 kHz set-point subsampled at 2 kHz.
  const Series ref = Sample(1000, 3.0, 0.0, true, false);
  const Series out = Sample(2000, 3.0, 0.0335, true, false);
  const DelayEstimate e = Estimate(ref, out);
  ASSERT_TRUE(e.ok());
  EXPECT_NEAR(e.delay_s, 0.0335, 0.5e-3);
}

// The leader's case: both displacements return to zero at the same tick (MotionTransfer::Rebase while the robot
// does not follow) and stay there for a while, then the motion resumes from zero. Differenced across the reset,
// the velocities hold a spike at the same time in both series, which pulls the lag to 0.
TEST(DelayEstimate, TheTransfersResetsAreRespected) {
  constexpr double kDelay = 0.035;
  Series ref = Sample(1000, 6.0, 0.0, true, false), out = Sample(1000, 6.0, kDelay, true, false);
  for (std::size_t k = 0; k < ref.t.size(); ++k) {
    if (ref.t[k] >= 2.0 && ref.t[k] < 2.3) {  // rebased: held at zero
      ref.x[k].setZero();
      out.x[k].setZero();
    } else if (ref.t[k] >= 2.3) {  // resumes from zero, wherever it was
      ref.x[k] -= Motion(2.3, true, false);
      out.x[k] -= Motion(2.3 - kDelay, true, false);
    }
  }
  const std::vector<int> segment = RebaseSegments(ref.x);
  EXPECT_NE(segment.front(), segment.back());
  const DelayEstimate e = EstimateDelay({.t_s = ref.t, .x = ref.x, .segment = segment},
                                        {.t_s = out.t, .x = out.x, .segment = segment});
  ASSERT_TRUE(e.ok()) << ToString(e.status);
  EXPECT_NEAR(e.delay_s, kDelay, 1e-3);
  // Without the segments the same data gives another lag (the test can fail).
  const DelayEstimate unsegmented = Estimate(ref, out);
  EXPECT_FALSE(unsegmented.ok() && std::fabs(unsegmented.delay_s - kDelay) < 1e-3) << unsegmented.delay_s;
}

// The hand is faster than the cap: the delayed set-point's velocity is the reference's clipped at the cap. Where the
// cap binds there is no single lag; when it binds most of the time, the estimate says so instead of a number.
TEST(DelayEstimate, AClippedDelayedSignalReportsTheCap) {
  constexpr double kDelay = 0.03;
  const Series ref = Sample(1000, 4.0, 0.0, true, false);
  std::vector<double> p_ref;
  for (const Vector6d& x : ref.x) p_ref.insert(p_ref.end(), x.data(), x.data() + 3);
  const std::vector<double> rates = RatesWithinSegments(ref.t, p_ref, 3);
  std::vector<double> speed(ref.t.size());
  for (std::size_t k = 0; k < ref.t.size(); ++k) speed[k] = Eigen::Vector3d(&rates[3 * k]).norm();
  const double v_max = *std::max_element(speed.begin(), speed.end());
  // The delayed copy through a rate limiter (the cap guard without its filters): the set-point moves toward the
  // delayed reference at most at `cap`, so while the cap binds it falls further behind, and then catches up.
  auto clipped = [&](double cap) {
    Series out = ref;
    Eigen::Vector3d y = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < ref.t.size(); ++k) {
      const Eigen::Vector3d target = Motion(std::max(0.0, ref.t[k] - kDelay), true, false).head<3>();
      if (k > 0) {
        const double dt = ref.t[k] - ref.t[k - 1];
        Eigen::Vector3d step = target - y;
        if (step.norm() > cap * dt) step *= cap * dt / step.norm();
        y += step;
      }
      out.x[k].head<3>() = y;
    }
    return out;
  };
  DelaySearch search;
  // The cap at 20 % of the peak speed: it binds nearly all the time.
  search.max_linear_speed_m_s = 0.2 * v_max;
  const DelayEstimate binds = Estimate(ref, clipped(search.max_linear_speed_m_s), search);
  EXPECT_EQ(binds.status, DelayStatus::kCapBinds) << ToString(binds.status) << " " << binds.delay_s;
  // Unaware of the cap, the estimator judges the clipped samples and gives a wrong lag (or none).
  const DelayEstimate unaware = Estimate(ref, clipped(search.max_linear_speed_m_s));
  EXPECT_FALSE(unaware.ok() && std::fabs(unaware.delay_s - kDelay) < 2e-3) << unaware.delay_s;
  // The cap at 90 % of the peak: it binds briefly; the rest gives the delay, on fewer samples.
  search.max_linear_speed_m_s = 0.9 * v_max;
  const DelayEstimate brief = Estimate(ref, clipped(search.max_linear_speed_m_s), search);
  ASSERT_TRUE(brief.ok()) << ToString(brief.status);
  EXPECT_NEAR(brief.delay_s, kDelay, 2e-3);
  EXPECT_LT(brief.judged_fraction(), 0.95);
  // The same through per-sample flags (the leader's eq. 11 scale below 1) instead of the caps.
  std::vector<std::uint8_t> capped(ref.t.size(), 0);
  for (std::size_t k = 0; k < ref.t.size(); ++k) {
    if (speed[k] >= 0.2 * v_max) capped[k] = kCappedLinear;
  }
  const Series low = clipped(0.2 * v_max);
  const DelayEstimate flagged =
      EstimateDelay({.t_s = ref.t, .x = ref.x, .capped = capped}, {.t_s = low.t, .x = low.x, .capped = capped});
  EXPECT_EQ(flagged.status, DelayStatus::kCapBinds) << ToString(flagged.status);
}

TEST(DelayEstimate, StatusCases) {
  const Series few = Sample(1000, 0.005, 0.0, true, false);
  EXPECT_EQ(Estimate(few, few).status, DelayStatus::kTooFewSamples);
  // Half a second of motion is less than kMinJudgedDuration_s: too few samples, no number.
  const Series half = Sample(1000, 0.5, 0.0, true, false), half_out = Sample(1000, 0.5, 0.01, true, false);
  EXPECT_EQ(Estimate(half, half_out).status, DelayStatus::kTooFewSamples);
  // A set-point that never moves: no motion.
  Series still = Sample(1000, 4.0, 0.0, true, false);
  const Series ref = still;
  for (Vector6d& x : still.x) x = Vector6d::Constant(0.01);
  EXPECT_EQ(Estimate(ref, still).status, DelayStatus::kNoMotion);
  EXPECT_STREQ(ToString(DelayStatus::kCapBinds), "cap_binds");
}

// A set-point sent short of the transfer's by more than the tolerance of a part marks that part as held back; a
// gap within it (the microns a following set-point trails by) marks nothing.
TEST(DelayEstimate, HeldBackMarksEachPartBeyondItsTolerance) {
  const Eigen::Isometry3d X = PoseFromMmDeg((Vector6d() << 10, -5, 284, 1, 2, 3).finished());
  const auto moved = [&](double dx_m, double angle_rad) {
    Eigen::Isometry3d Y = X;
    Y.translation().x() += dx_m;
    Y.linear() = Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix() * X.linear();
    return Y;
  };
  EXPECT_EQ(HeldBack(X, X), 0);
  EXPECT_EQ(HeldBack(X, moved(0.5 * kHeldBackLinear_m, 0.5 * kHeldBackAngular_rad)), 0);
  EXPECT_EQ(HeldBack(X, moved(2 * kHeldBackLinear_m, 0)), kCappedLinear);
  EXPECT_EQ(HeldBack(X, moved(0, 2 * kHeldBackAngular_rad)), kCappedAngular);
  EXPECT_EQ(HeldBack(X, moved(-0.02, 0.1)), kCappedLinear | kCappedAngular);
}

}  // namespace
}  // namespace robossis::teleop
