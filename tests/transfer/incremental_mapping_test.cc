// eq. 10–11: increments, the dynamic scaling cap, frame mapping, clutch and stream hygiene.

#include <cmath>

#include <gtest/gtest.h>

#include "haptics/transfer/incremental_mapping.h"
#include "src/core/units.h"

namespace robossis::transfer {
namespace {

HcSample At(double t, double x_m, double yaw_rad = 0) {
  HcSample s;
  s.time_s = t;
  s.p_OH = Eigen::Vector3d(x_m, 0, 0);
  s.R_OH = RotationFromRpy(Eigen::Vector3d(0, 0, yaw_rad));
  return s;
}

MappingConfig NoHeadroom() {
  MappingConfig m;
  m.cap_headroom = 1.0;
  return m;
}

TEST(IncrementalMappingTest, SlowHandPassesUnchanged) {
  IncrementalMapper mapper(NoHeadroom(), SpeedCaps{});
  MappingIncrement inc;
  EXPECT_EQ(mapper.Push(At(0.000, 0.0), inc), SampleVerdict::kAnchored);
  // 5 µm in 1 ms = 5 mm/s < 10 mm/s: S = 1, eq. 10 passes the increment as is.
  ASSERT_EQ(mapper.Push(At(0.001, 5e-6), inc), SampleVerdict::kAccepted);
  EXPECT_DOUBLE_EQ(inc.scale_linear, 1.0);
  EXPECT_NEAR(inc.delta_F[0], 5e-6, 1e-18);
}

TEST(IncrementalMappingTest, FastHandIsScaledToTheCap) {
  IncrementalMapper mapper(NoHeadroom(), SpeedCaps{});
  MappingIncrement inc;
  mapper.Push(At(0.000, 0.0), inc);
  // 20 µm in 1 ms = 20 mm/s: eq. 11 gives S = 10/20, the RSR moves at exactly 10 mm/s.
  ASSERT_EQ(mapper.Push(At(0.001, 20e-6), inc), SampleVerdict::kAccepted);
  EXPECT_NEAR(inc.scale_linear, 0.5, 1e-12);
  EXPECT_NEAR(inc.delta_F.head<3>().norm() / 0.001, 0.010, 1e-12);
}

TEST(IncrementalMappingTest, AngularCapOnTheNorm) {
  IncrementalMapper mapper(NoHeadroom(), SpeedCaps{});
  MappingIncrement inc;
  mapper.Push(At(0.0, 0.0, 0.0), inc);
  ASSERT_EQ(mapper.Push(At(0.001, 0.0, DegToRad(0.005)), inc), SampleVerdict::kAccepted);  // 5 deg/s
  EXPECT_NEAR(RadToDeg(inc.delta_F.tail<3>().norm()) / 0.001, 1.0, 1e-9);
}

TEST(IncrementalMappingTest, RepeatedSamplesWidenTheGapInsteadOfMakingASpike) {
  IncrementalMapper mapper(NoHeadroom(), SpeedCaps{});
  MappingIncrement inc;
  mapper.Push(At(0.000, 0.0), inc);
  for (int k = 1; k < 10; ++k) EXPECT_EQ(mapper.Push(At(k * 1e-3, 0.0), inc), SampleVerdict::kRepeated);
  // 50 µm after a 10 ms freeze is 5 mm/s over the gap, not 50 mm/s over one period: passed whole.
  ASSERT_EQ(mapper.Push(At(0.010, 50e-6), inc), SampleVerdict::kAccepted);
  EXPECT_NEAR(inc.hc_speed_m_s, 0.005, 1e-12);
  EXPECT_DOUBLE_EQ(inc.scale_linear, 1.0);
}

TEST(IncrementalMappingTest, LateAndInvalidSamplesAreIgnored) {
  IncrementalMapper mapper(NoHeadroom(), SpeedCaps{});
  MappingIncrement inc;
  mapper.Push(At(0.000, 0.0), inc);
  mapper.Push(At(0.002, 1e-6), inc);
  EXPECT_EQ(mapper.Push(At(0.001, 5e-6), inc), SampleVerdict::kLate);
  EXPECT_EQ(mapper.Push(At(0.002, 5e-6), inc), SampleVerdict::kLate);
  EXPECT_EQ(mapper.Push(At(0.003, std::nan("")), inc), SampleVerdict::kInvalid);
  EXPECT_EQ(inc.delta_F, Vector6d::Zero());
  ASSERT_EQ(mapper.Push(At(0.003, 2e-6), inc), SampleVerdict::kAccepted);
  EXPECT_NEAR(inc.delta_F[0], 1e-6, 1e-18);  // from the last sample used, not from the late one
}

TEST(IncrementalMappingTest, ClutchReleaseAndEngageNeverJump) {
  IncrementalMapper mapper(NoHeadroom(), SpeedCaps{});
  MappingIncrement inc;
  mapper.Push(At(0.000, 0.0), inc);
  mapper.SetClutch(false);
  EXPECT_EQ(mapper.Push(At(0.5, 0.05), inc), SampleVerdict::kClutchOpen);  // the hand moves 50 mm while released
  mapper.SetClutch(true);
  EXPECT_EQ(mapper.Push(At(0.6, 0.06), inc), SampleVerdict::kAnchored);  // re-anchored: no increment
  ASSERT_EQ(mapper.Push(At(0.601, 0.060001), inc), SampleVerdict::kAccepted);
  EXPECT_NEAR(inc.delta_F[0], 1e-6, 1e-15);
}

TEST(IncrementalMappingTest, FrameMappingRotatesIncrements) {
  MappingConfig m = NoHeadroom();
  m.R_FO = RotationFromRpy(Eigen::Vector3d(0, 0, kPi / 2));  // HC x is RSR y
  IncrementalMapper mapper(m, SpeedCaps{});
  MappingIncrement inc;
  mapper.Push(At(0.0, 0.0), inc);
  ASSERT_EQ(mapper.Push(At(0.001, 2e-6), inc), SampleVerdict::kAccepted);
  EXPECT_NEAR(inc.delta_F[0], 0.0, 1e-18);
  EXPECT_NEAR(inc.delta_F[1], 2e-6, 1e-18);
}

}  // namespace
}  // namespace robossis::transfer
