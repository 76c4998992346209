// Our proxy (god-object) method: kept on the true boundary, force along the true normal.

#include <cmath>
#include <random>

#include <vector>

#include <gtest/gtest.h>

#include "haptics/rendering/boundary_probe.h"
#include "haptics/rendering/proxy_renderer.h"
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

ProxyRenderer MakeProxy() {
  return ProxyRenderer(Rsr(), IdentityMap(), Config().limits, 1000, Config().wall, Config().proxy);
}

TEST(Proxy, FreeSpaceIsOnlyViscous) {
  ProxyRenderer r = MakeProxy();
  r.Reset(Home());
  const Eigen::Vector3d v(0.02, 0, -0.01);
  const HapticOutput out = Hold(r, Home(), 3, v);
  EXPECT_EQ(out.status, HapticStatus::kFree);
  EXPECT_TRUE(out.f_O.isApprox(-Config().wall.c_f_ns_per_m * v, 1e-12));
  EXPECT_TRUE(r.proxy_pose().isApprox(Home(), 1e-12));
}

TEST(Proxy, StaysFeasibleOnARandomWalkThatLeavesTheWorkspace) {
  ProxyRenderer r = MakeProxy();
  r.Reset(Home());
  std::mt19937 gen{42};
  std::normal_distribution<double> step(0, 1.0);
  Eigen::Isometry3d X = Home();
  HapticInput in;
  HapticOutput out;
  for (int k = 0; k < 3000; ++k) {
    // A drifting walk (mean +x and +roll) that goes well beyond the edges.
    X.translation() += 1e-3 * Eigen::Vector3d(step(gen) + 0.3, step(gen), step(gen));
    X.linear() = RotationFromVector(2e-3 * Eigen::Vector3d(step(gen) + 0.2, step(gen), step(gen))) * X.linear();
    in.X_OH = X;
    r.Tick(in, out);
    ASSERT_TRUE(robot::IsPoseFeasible(Rsr(), r.proxy_pose())) << "tick " << k;
    ASSERT_TRUE(out.f_O.allFinite());
    ASSERT_LE(out.f_O.norm(), Config().limits.max_force_n + 1e-9);
    ASSERT_LE(out.tau_O.norm(), Config().limits.max_torque_nm + 1e-9);
  }
  EXPECT_FALSE(robot::IsPoseFeasible(Rsr(), X));  // the walk did leave the workspace
}

TEST(Proxy, ForceFollowsTheTrueNormalBeyondEveryEdge) {
  ProxyRenderer r = MakeProxy();
  for (const Eigen::Vector3d& axis : std::vector<Eigen::Vector3d>{Eigen::Vector3d::UnitX(), Eigen::Vector3d(0, -1, 0), Eigen::Vector3d::UnitZ(),
                                     Eigen::Vector3d(0, 0, -1)}) {
    const double reach = ReachAlongAxis(Rsr(), Home(), axis, false, 0.3);
    r.Reset(Home());
    // Walk out to 3 mm beyond the edge.
    for (double s = 0; s <= reach + 0.003; s += 0.0005) Hold(r, Translated(Home(), s * axis), 1);
    const Eigen::Isometry3d X = Translated(Home(), (reach + 0.003) * axis);
    const HapticOutput out = Hold(r, X, 1);
    ASSERT_EQ(out.status, HapticStatus::kContact);
    // Spring: k_f · (proxy − HC); 3 mm beyond a face: about 6 N, and the proxy on the boundary.
    EXPECT_GT(out.f_O.norm(), 4.0);
    const Eigen::Vector3d n = InwardNormalTranslation(Rsr(), r.proxy_pose());
    EXPECT_GT(out.f_O.normalized().dot(n), std::cos(5.0 * 3.14159265358979 / 180)) << axis.transpose();
    EXPECT_LT(TightestLimit(Rsr(), r.proxy_pose()).margin, 1e-4);  // on the boundary
  }
}

TEST(Proxy, SlidesAlongACurvedBoundary) {
  // Beyond the +x edge the three spherical-cone limits coincide on a curved (conical) surface; moving the HC
  // sideways must drag the proxy along it, not pin it (a tangent step alone leaves a convex surface at once).
  ProxyRenderer r = MakeProxy();
  const double reach = ReachAlongAxis(Rsr(), Home(), Eigen::Vector3d::UnitX(), false, 0.3);
  r.Reset(Home());
  for (double s = reach - 0.005; s <= reach + 0.002; s += 0.0005) {
    Hold(r, Translated(Home(), s * Eigen::Vector3d::UnitX()), 1);
  }
  for (int k = 1; k <= 100; ++k) {
    Hold(r, Translated(Home(), Eigen::Vector3d(reach + 0.002, 1e-4 * k, 0)), 1);
  }
  EXPECT_NEAR(r.proxy_pose().translation().y() - Home().translation().y(), 0.01, 1e-3);
  EXPECT_TRUE(robot::IsPoseFeasible(Rsr(), r.proxy_pose()));
}

}  // namespace
}  // namespace robossis::haptics
