// The whole 1 kHz → 10 kHz pipeline: caps on the norm, continuity, breakage, clutch, zero allocations.

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "haptics/transfer/hc_trajectory.h"
#include "haptics/transfer/motion_transfer.h"
#include "src/core/units.h"
#include "tests/support/alloc_counter.h"

namespace robossis::transfer {
namespace {

struct Peaks {
  double speed = 0, angular_speed = 0, dp = 0, dv = 0, da = 0, finite_diff_speed = 0;
  bool finite = true;
};

// Replays records (arrival order) through the pipeline and measures per-tick changes of the set-point.
Peaks Replay(MotionTransfer& mt, const std::vector<HcRecord>& records, double t_end) {
  Peaks pk;
  std::size_t next = 0;
  Vector6d prev_x = Vector6d::Zero(), prev_v = Vector6d::Zero(), prev_a = Vector6d::Zero();
  const int n = static_cast<int>(t_end * 1000);
  for (int k = 0; k < n; ++k) {
    const double t = k * 1e-3;
    while (next < records.size() && records[next].arrival_s <= t + 1e-12) {
      mt.SetClutch(records[next].clutch);
      mt.PushHcSample(records[next++].ToSample());
    }
    mt.TransferTick();
    for (int j = 0; j < 10; ++j) {
      const RsrSetPoint& sp = mt.ActuationTick();
      pk.finite = pk.finite && sp.displacement.allFinite() && sp.X_FM.matrix().allFinite();
      pk.speed = std::max(pk.speed, sp.velocity.head<3>().norm());
      pk.angular_speed = std::max(pk.angular_speed, sp.velocity.tail<3>().norm());
      pk.finite_diff_speed = std::max(pk.finite_diff_speed, (sp.displacement - prev_x).head<3>().norm() / 1e-4);
      pk.dp = std::max(pk.dp, (sp.displacement - prev_x).head<3>().norm());
      pk.dv = std::max(pk.dv, (sp.velocity - prev_v).head<3>().norm());
      pk.da = std::max(pk.da, (sp.acceleration - prev_a).head<3>().norm());
      prev_x = sp.displacement;
      prev_v = sp.velocity;
      prev_a = sp.acceleration;
    }
  }
  return pk;
}

// A hand far beyond the caps: random jerky motion at up to ~200 mm/s and 50 deg/s, with breakage-like gaps.
std::vector<HcRecord> WildHand() {
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> u(-1.0, 1.0), coin(0.0, 1.0);
  std::vector<HcRecord> out;
  Vector6d x = Vector6d::Zero(), v = Vector6d::Zero();
  for (int k = 0; k < 3000; ++k) {
    for (int i = 0; i < 6; ++i) v[i] = std::clamp(v[i] + 20 * u(gen), -200.0, 200.0);
    x.head<3>() += v.head<3>() * 1e-3;
    x.tail<3>() += 0.25 * v.tail<3>() * 1e-3;
    if (coin(gen) < 0.02) continue;  // dropped
    HcRecord r;
    r.time_s = r.arrival_s = k * 1e-3;
    r.pose_mm_deg = x;
    out.push_back(r);
  }
  return out;
}

TEST(MotionTransferTest, CapsAreNeverExceededOnTheNorm) {
  TransferConfig config;
  MotionTransfer mt(config, Eigen::Isometry3d::Identity());
  const Peaks pk = Replay(mt, WildHand(), 3.5);
  ASSERT_TRUE(pk.finite);
  EXPECT_LE(pk.speed, config.caps.max_linear_speed_m_s);
  EXPECT_LE(pk.angular_speed, config.caps.max_angular_speed_rad_s);
  // The set-point itself (finite difference of positions), not only the reported velocity.
  EXPECT_LE(pk.finite_diff_speed, config.caps.max_linear_speed_m_s * (1 + 1e-9));
}

TEST(MotionTransferTest, ClinicalCapsHoldToo) {
  TransferConfig config;
  config.caps.max_linear_speed_m_s = MmToM(2.0);  // [paper §V] clinical
  config.caps.max_angular_speed_rad_s = DegToRad(0.2);
  MotionTransfer mt(config, Eigen::Isometry3d::Identity());
  const Peaks pk = Replay(mt, MakeScenario("fig8").records, 9.0);
  EXPECT_LE(pk.speed, MmToM(2.0));
  EXPECT_LE(pk.angular_speed, DegToRad(0.2));
}

TEST(MotionTransferTest, PositionVelocityAndAccelerationAreContinuousThroughBreakage) {
  // Fig. 8 breakage (dropouts, frozen and late samples, a 200 ms stall): the raw HC jumps, the set-point does not.
  TransferConfig config;
  MotionTransfer mt(config, Eigen::Isometry3d::Identity());
  const HcTrajectory hc = MakeScenario("fig8");
  const Peaks pk = Replay(mt, hc.records, 9.5);
  ASSERT_TRUE(pk.finite);
  const double dt = 1e-4;
  EXPECT_LE(pk.dp, config.caps.max_linear_speed_m_s * dt * (1 + 1e-9));  // position: at most cap · dt per tick
  EXPECT_LE(pk.dv / dt, 1.0);    // velocity: |a| < 1 m/s^2 (1000 mm/s^2): no velocity jump
  EXPECT_LE(pk.da / dt, 100.0);  // acceleration: |jerk| < 100 m/s^3: no acceleration jump
  // The raw HC as delivered has velocity spikes far beyond these bounds (the breakage of Fig. 8c).
  double raw_peak = 0;
  for (std::size_t i = 1; i < hc.records.size(); ++i) {
    const double dp = (hc.records[i].pose_mm_deg - hc.records[i - 1].pose_mm_deg).head<3>().norm() * 1e-3;
    raw_peak = std::max(raw_peak, dp / 1e-3);
  }
  EXPECT_GT(raw_peak, 0.1);  // > 100 mm/s per sample
  EXPECT_GT(mt.counters().repeated, 0u);
  EXPECT_GT(mt.counters().late, 0u);
}

TEST(MotionTransferTest, DropoutsAndRepeatsLoseNoMotionBelowTheCap) {
  // A slow hand (5 mm/s) with a gap and a freeze: the RSR ends exactly where the hand's increments add up to.
  std::vector<HcRecord> recs;
  for (int k = 0; k <= 2000; ++k) {
    HcRecord r;
    r.time_s = r.arrival_s = k * 1e-3;
    const double t = std::min(r.time_s, 1.5);
    r.pose_mm_deg[0] = 5.0 * t;  // mm
    if (k > 300 && k < 340) continue;                                  // dropout
    if (k >= 600 && k < 630) r.pose_mm_deg[0] = 5.0 * 0.6;             // frozen
    recs.push_back(r);
  }
  TransferConfig config;
  MotionTransfer mt(config, Eigen::Isometry3d::Identity());
  Replay(mt, recs, 3.0);
  EXPECT_NEAR(mt.set_point().displacement[0], MmToM(7.5), 1e-7);
  EXPECT_GT(mt.counters().repeated, 0u);
}

TEST(MotionTransferTest, ClutchNeverMakesTheFollowerJump) {
  const HcTrajectory hc = MakeScenario("clutch");
  TransferConfig config;
  MotionTransfer mt(config, Eigen::Isometry3d::Identity());
  const Peaks pk = Replay(mt, hc.records, 9.5);
  EXPECT_LE(pk.dp, config.caps.max_linear_speed_m_s * 1e-4 * (1 + 1e-9));
  EXPECT_LE(pk.dv / 1e-4, 1.0);
  EXPECT_GT(mt.counters().clutch_open, 500u);
}

TEST(MotionTransferTest, TicksAllocateNothing) {
  TransferConfig config;
  MotionTransfer mt(config, Eigen::Isometry3d::Identity());
  const std::vector<HcRecord> recs = MakeScenario("fig8").records;
  std::vector<HcSample> samples;
  for (const HcRecord& r : recs) samples.push_back(r.ToSample());
  const testing::AllocationCounter counter;
  std::size_t i = 0;
  for (int k = 0; k < 2000; ++k) {
    if (i < samples.size()) mt.PushHcSample(samples[i++]);  // the 1 kHz transfer tick
    mt.TransferTick();
    for (int j = 0; j < 10; ++j) mt.ActuationTick();  // the 10 kHz part
  }
  EXPECT_EQ(counter.count(), 0u);
}

TEST(MotionTransferTest, OrientationFollowsTheAngularIncrements) {
  // A pure twist below the angular cap: the set-point rotation equals the hand's.
  std::vector<HcRecord> recs;
  for (int k = 0; k <= 2000; ++k) {
    HcRecord r;
    r.time_s = r.arrival_s = k * 1e-3;
    r.pose_mm_deg[5] = 0.5 * std::min(r.time_s, 1.0);  // 0.5 deg/s for 1 s
    recs.push_back(r);
  }
  TransferConfig config;
  const Eigen::Isometry3d start = PoseFromMmDeg((Vector6d() << 0, 0, 284, 1, 2, 3).finished());
  MotionTransfer mt(config, start);
  Replay(mt, recs, 3.0);
  const Eigen::Matrix3d expected = RotationFromRpy(Eigen::Vector3d(0, 0, DegToRad(0.5))) * start.linear();
  EXPECT_LT(RadToDeg(RotationAngleBetween(mt.set_point().X_FM.linear(), expected)), 1e-6);
}

}  // namespace
}  // namespace robossis::transfer
