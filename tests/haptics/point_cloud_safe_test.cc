// The device-safe preset of the paper's point-cloud method (pointcloud-safe: k_τ = 1 N·m/rad) on a short pitch
// push: it must be passive, and its force must not point across the workspace (haptics/README.md, "Why
// pointcloud-safe generated energy"). Before the fix the translational cloud, evaluated at the turned orientation,
// pushed the hand sideways out of the narrowing workspace: ~0.1 J generated and a force ~100° off the normal.

#include <algorithm>

#include <gtest/gtest.h>

#include "haptics/rendering/point_cloud_renderer.h"
#include "haptics/scenarios/compare.h"
#include "src/core/units.h"
#include "test_util.h"

namespace robossis::haptics {
namespace {

using testing::Config;
using testing::Rsr;

// The pitch+ edge of push-edges, shortened: from 5.5° inside (both clouds free) to 2° beyond at 2°/s, held 0.5 s.
Scenario ShortPitchPush() {
  const Scenario full = MakeScenario("push-edges", Rsr(), Config().hand, Config().strike_hand_stiffness_n_per_m, false);
  Episode e;
  for (const Episode& candidate : full.episodes) {
    if (candidate.label == "pitch+") e = candidate;
  }
  const double s0 = e.boundary_s - DegToRad(5.5), s1 = e.boundary_s + DegToRad(2), speed = DegToRad(2);
  const double travel_s = (s1 - s0) / speed;
  const Eigen::Isometry3d home = e.X_FM_reference;
  const Eigen::Vector3d axis = e.axis;
  auto at = [home, axis](double s) -> Eigen::Isometry3d {
    Eigen::Isometry3d X = home;
    X.linear() = RotationFromVector(s * axis) * home.linear();
    return X;
  };
  e.duration_s = travel_s + 0.5;
  e.X_FM_start = at(s0);
  e.X_FM_anchor = e.X_FM_start;
  e.target_FM = [=](double t) -> Eigen::Isometry3d { return at(s0 + speed * std::min(t, travel_s)); };
  Scenario s;
  s.name = "pitch-push";
  s.episodes.push_back(e);
  return s;
}

MethodRun RunShortPitchPush(const char* method) {
  HapticsConfig config = Config();
  config.cloud.translation_points = 100;  // [assumed] enough for the effect, half the cost of the default 200
  config.cloud.rotation_points = 100;
  CompareSettings settings;
  settings.keep_trace = false;
  return RunMethod(ShortPitchPush(), method, config, Rsr(), robot::Sigma7Model::Default(), settings);
}

TEST(PointCloudSafe, ThePresetIsASoftTorqueWallThePaperPresetIsNot) {
  // The torque at the boundary (half the rotational cloud inside): k_τ·r_rot/2.
  const HcToRsrMap map;
  const PointCloudRenderer paper(Rsr(), map, Config().limits, 1000, Config().wall, Config().cloud);
  const PointCloudRenderer safe(Rsr(), map, Config().limits, 1000, Config().device_safe_wall, Config().cloud);
  EXPECT_NEAR(paper.torque_at_boundary_nm(), 0.3, 1e-9);  // 0.12 N·m/deg × 2.5°: the paper's cap, §VI-B
  EXPECT_NEAR(safe.torque_at_boundary_nm(), 0.0175 * 2.5, 1e-9);
  EXPECT_TRUE(paper.holds_orientation());
  EXPECT_FALSE(safe.holds_orientation());
}

TEST(PointCloudSafe, PitchPushIntoTheTiltLimitGeneratesNoEnergy) {
  const MethodRun run = RunShortPitchPush("pointcloud-safe");
  // Before the fix: 0.1 J on this segment (0.35 J over the twelve edges of push-edges).
  EXPECT_LT(run.metrics.energy_generated_j, 1e-4);
  EXPECT_EQ(run.metrics.fault_ticks, 0);
}

TEST(PointCloudSafe, PitchPushForceAndTorquePointAlongTheTrueNormal) {
  const MethodRun run = RunShortPitchPush("pointcloud-safe");
  // Before the fix: ~100° (a 5–8 N force along the slab of the tilted workspace, not toward its nearest wall).
  EXPECT_LT(run.metrics.direction_error_deg_p95, 30.0);
  // The soft torque wall yields in rotation (like proxy-safe): the hand goes past the tilt limit a little.
  EXPECT_GT(run.metrics.max_penetration_deg, 0.1);
  EXPECT_LT(run.metrics.max_penetration_deg, 3.0);
}

}  // namespace
}  // namespace robossis::haptics
