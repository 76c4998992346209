// The linearly weighted moving average of paper §VI-A and the spring-damper law of eq. 18–19.

#include <gtest/gtest.h>

#include "haptics/rendering/wall_law.h"

namespace robossis::haptics {
namespace {

Vector6d Sample(double x) {
  Vector6d v = Vector6d::Zero();
  v[0] = x;
  return v;
}

TEST(WeightedMovingAverage, WeightsAreLinearNewestHeaviest) {
  // Paper §VI-A: window 5, linear weights, latest highest: 1/15, 2/15, ..., 5/15.
  WeightedMovingAverage f(5);
  for (int age = 0; age < 5; ++age) EXPECT_NEAR(f.Weight(age), (5.0 - age) / 15.0, 1e-15);
  EXPECT_EQ(f.Weight(5), 0.0);
  // Samples 1..5 (5 newest): (1·1 + 2·2 + 3·3 + 4·4 + 5·5)/15 = 55/15.
  Vector6d out;
  for (int k = 1; k <= 5; ++k) out = f.Filter(Sample(k));
  EXPECT_NEAR(out[0], 55.0 / 15.0, 1e-12);
  // A sixth sample drops the oldest: (2·1 + 3·2 + 4·3 + 5·4 + 6·5)/15 = 70/15.
  out = f.Filter(Sample(6));
  EXPECT_NEAR(out[0], 70.0 / 15.0, 1e-12);
}

TEST(WeightedMovingAverage, RenormalisesWhileFilling) {
  WeightedMovingAverage f(5);
  EXPECT_NEAR(f.Filter(Sample(3))[0], 3.0, 1e-12);                  // one sample: itself
  EXPECT_NEAR(f.Filter(Sample(6))[0], (3.0 * 1 + 6.0 * 2) / 3, 1e-12);  // weights 1/3, 2/3
}

TEST(WeightedMovingAverage, RejectsBadWindow) {
  EXPECT_THROW(WeightedMovingAverage(0), std::invalid_argument);
  EXPECT_THROW(WeightedMovingAverage(WeightedMovingAverage::kMaxWindow + 1), std::invalid_argument);
}

TEST(WallLaw, SpringPushesAlongInwardVectorAndDamperOpposesVelocity) {
  const WallLawParams p;  // paper constants
  const Eigen::Vector3d f = WallForce(p, Eigen::Vector3d(0, 0, -0.005), Eigen::Vector3d(0.01, 0, 0));
  // eq. 18: 2000 N/m · 5 mm = 10 N along d_in; 15 N·s/m · 10 mm/s = 0.15 N against v.
  EXPECT_NEAR(f.z(), -10.0, 1e-12);
  EXPECT_NEAR(f.x(), -0.15, 1e-12);
  // eq. 19: 0.12 N·m/deg · 1 deg = 0.12 N·m.
  const Eigen::Vector3d tau = WallTorque(p, Eigen::Vector3d(3.14159265358979323846 / 180, 0, 0),
                                         Eigen::Vector3d::Zero());
  EXPECT_NEAR(tau.x(), 0.12, 1e-12);
}

}  // namespace
}  // namespace robossis::haptics
