// The paper's point-cloud method (Algorithm 1, eq. 18–21).

#include <cmath>
#include <random>

#include <vector>

#include <gtest/gtest.h>

#include "haptics/rendering/boundary_probe.h"
#include "haptics/rendering/point_cloud_renderer.h"
#include "haptics/scenarios/scenario.h"
#include "test_util.h"

namespace robossis::haptics {
namespace {

using testing::Config;
using testing::Hold;
using testing::Home;
using testing::IdentityMap;
using testing::Rsr;
using testing::Translated;

PointCloudParams SmallCloud(int n = 60) {
  PointCloudParams p = Config().cloud;
  p.translation_points = n;
  p.rotation_points = n;
  return p;
}

TEST(PointCloud, OnlyViscousForceDeepInside) {
  PointCloudRenderer r(Rsr(), IdentityMap(), Config().limits, 1000, Config().wall, SmallCloud());
  r.Reset(Home());
  const Eigen::Vector3d v(0.01, -0.02, 0.005);
  HapticInput in;
  in.X_OH = Home();
  in.v_O = v;
  in.w_O = Eigen::Vector3d(0.1, 0, -0.05);
  HapticOutput out;
  for (int k = 0; k < 6; ++k) r.Tick(in, out);
  EXPECT_EQ(out.status, HapticStatus::kFree);
  EXPECT_EQ(r.translation_points_outside(), 0);
  EXPECT_EQ(r.rotation_points_outside(), 0);
  // Algorithm 1 lines 19–20: F = −c_f v, τ = −c_τ ω (constant input: the moving average returns it unchanged).
  EXPECT_TRUE(out.f_O.isApprox(-Config().wall.c_f_ns_per_m * v, 1e-12));
  EXPECT_TRUE(out.tau_O.isApprox(-Config().wall.c_tau_nms_per_rad * in.w_O, 1e-12));
}

TEST(PointCloud, ForcePointsBackIntoTheWorkspaceNearEveryEdge) {
  PointCloudRenderer r(Rsr(), IdentityMap(), Config().limits, 1000, Config().wall, SmallCloud(120));
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> offset_mm(-12, 6);  // from inside the cloud's reach to beyond the edge
  int checked = 0;
  for (const Eigen::Vector3d& axis : std::vector<Eigen::Vector3d>{Eigen::Vector3d::UnitX(), Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d::UnitY(),
                                     Eigen::Vector3d(0, -1, 0), Eigen::Vector3d::UnitZ(), Eigen::Vector3d(0, 0, -1)}) {
    const double reach = ReachAlongAxis(Rsr(), Home(), axis, false, 0.3);
    for (int k = 0; k < 5; ++k) {
      const Eigen::Isometry3d X = Translated(Home(), (reach + offset_mm(gen) * 1e-3) * axis);
      r.Reset(X);
      const HapticOutput out = Hold(r, X);
      ASSERT_NE(out.status, HapticStatus::kFree);
      // The true inward normal (IK margins), independent of the method.
      const Eigen::Vector3d n = InwardNormalTranslation(Rsr(), X);
      EXPECT_GT(out.f_O.normalized().dot(n), std::cos(30.0 * 3.14159265358979 / 180))
          << "axis " << axis.transpose() << " force " << out.f_O.transpose() << " normal " << n.transpose();
      ++checked;
    }
  }
  EXPECT_EQ(checked, 30);
}

TEST(PointCloud, ForceAtTheBoundaryIsTheSaturationValue) {
  // Our reading of eq. 20 (surface points, mean of the inside offsets): on a flat stretch of boundary half the
  // cloud is inside, d = r/2 = 7.5 mm, k_f·d = 15 N — the paper's "maximum at the edge" (§VI-B, Fig. 11).
  PointCloudRenderer r(Rsr(), IdentityMap(), Config().limits, 1000, Config().wall, SmallCloud(2000));
  const double reach = ReachAlongAxis(Rsr(), Home(), Eigen::Vector3d::UnitZ(), false, 0.3);
  const Eigen::Isometry3d X = Translated(Home(), reach * Eigen::Vector3d::UnitZ());
  r.Reset(X);
  Hold(r, X, 1);
  EXPECT_NEAR(r.last_penetration_translation().norm(), 7.5e-3, 0.4e-3);
}

TEST(PointCloud, SaturationIsNeverExceeded) {
  PointCloudRenderer r(Rsr(), IdentityMap(), Config().limits, 1000, Config().wall, SmallCloud());
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> pos(-0.25, 0.25), ang(-0.6, 0.6), vel(-2, 2);
  r.Reset(Home());
  HapticInput in;
  HapticOutput out;
  for (int k = 0; k < 2000; ++k) {
    in.X_OH = Home();
    in.X_OH.translation() += Eigen::Vector3d(pos(gen), pos(gen), pos(gen));
    in.X_OH.linear() = RotationFromVector(Eigen::Vector3d(ang(gen), ang(gen), ang(gen)));
    in.v_O = Eigen::Vector3d(vel(gen), vel(gen), vel(gen));
    in.w_O = Eigen::Vector3d(vel(gen), vel(gen), vel(gen)) * 5;
    r.Tick(in, out);
    ASSERT_TRUE(out.f_O.allFinite() && out.tau_O.allFinite());
    ASSERT_LE(out.f_O.norm(), Config().limits.max_force_n + 1e-9);
    ASSERT_LE(out.tau_O.norm(), Config().limits.max_torque_nm + 1e-9);
  }
}

TEST(PointCloud, FarOutsideGivesBoundedFiniteForceAndDeepStatus) {
  PointCloudRenderer r(Rsr(), IdentityMap(), Config().limits, 1000, Config().wall, SmallCloud());
  // Walk out along +x from inside (the last inward direction is remembered), then jump far away.
  const double reach = ReachAlongAxis(Rsr(), Home(), Eigen::Vector3d::UnitX(), false, 0.3);
  r.Reset(Home());
  for (double s = reach - 0.01; s < reach + 0.05; s += 0.001) Hold(r, Translated(Home(), s * Eigen::Vector3d::UnitX()), 1);
  const HapticOutput out = Hold(r, Translated(Home(), Eigen::Vector3d(0.5, 0, 0)));
  EXPECT_EQ(out.status, HapticStatus::kDeepPenetration);
  ASSERT_TRUE(out.f_O.allFinite());
  EXPECT_NEAR(out.f_O.norm(), Config().limits.max_force_n, 1e-9);
  EXPECT_LT(out.f_O.x(), 0);  // still pushing back toward the workspace
  // A cold start far outside (no history): toward home, still bounded.
  r.Reset(Home());
  const HapticOutput cold = Hold(r, Translated(Home(), Eigen::Vector3d(0, 0, 1.0)));
  ASSERT_TRUE(cold.f_O.allFinite());
  EXPECT_LT(cold.f_O.z(), 0);
}

TEST(PointCloud, NonFiniteInputIsAFault) {
  PointCloudRenderer r(Rsr(), IdentityMap(), Config().limits, 1000, Config().wall, SmallCloud());
  HapticInput in;
  in.X_OH = Home();
  in.v_O.x() = std::nan("");
  HapticOutput out;
  EXPECT_EQ(r.Tick(in, out), HapticStatus::kFault);
  EXPECT_TRUE(out.f_O.isZero());
}

}  // namespace
}  // namespace robossis::haptics
