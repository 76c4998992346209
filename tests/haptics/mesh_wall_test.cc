// Mesh walls on the geometry module's boundary atlas (FCL signed penetration).

#include <filesystem>
#include <memory>

#include <vector>

#include <gtest/gtest.h>

#include "haptics/rendering/boundary_probe.h"
#include "haptics/rendering/mesh_wall_renderer.h"
#include "haptics/scenarios/scenario.h"
#include "src/core/pose.h"
#include "src/core/units.h"
#include "test_util.h"
#include "tests/support/scratch_dir.h"
#include "tests/support/alloc_counter.h"

namespace robossis::haptics {
namespace {

using testing::Config;
using testing::Hold;
using testing::Home;
using testing::IdentityMap;
using testing::Rsr;
using testing::Translated;
using geometry::LiveBoundaryOptions;

class MeshWall : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<robossis::testing::ScratchDir>("robossis_haptics_test_atlas");
    atlas_ = std::make_shared<const geometry::BoundaryAtlas>(geometry::BuildAtlas(
        Rsr(), robot::Sigma7Model::Default(), geometry::AtlasSpec::Coarse(Rsr()), dir_->path() / "atlas"));
  }
  static void TearDownTestSuite() {
    atlas_.reset();
    dir_.reset();
  }
  static std::unique_ptr<robossis::testing::ScratchDir> dir_;
  static std::shared_ptr<const geometry::BoundaryAtlas> atlas_;
  MeshWallRenderer Make() {
    return MeshWallRenderer(Rsr(), IdentityMap(), Config().limits, 1000, Config().wall, 5, atlas_);
  }
};
std::shared_ptr<const geometry::BoundaryAtlas> MeshWall::atlas_;
std::unique_ptr<robossis::testing::ScratchDir> MeshWall::dir_;

TEST_F(MeshWall, ViscousOnlyInside) {
  MeshWallRenderer r = Make();
  r.Reset(Home());
  const Eigen::Vector3d v(0.01, 0, 0);
  const HapticOutput out = Hold(r, Home(), 6, v);
  EXPECT_EQ(out.status, HapticStatus::kFree);
  EXPECT_TRUE(out.f_O.isApprox(-Config().wall.c_f_ns_per_m * v, 1e-12));
}

TEST_F(MeshWall, PushesBackBeyondTheTopAndBottomEdges) {
  MeshWallRenderer r = Make();
  for (const Eigen::Vector3d& axis : std::vector<Eigen::Vector3d>{Eigen::Vector3d::UnitZ(), Eigen::Vector3d(0, 0, -1)}) {
    const double reach = ReachAlongAxis(Rsr(), Home(), axis, false, 0.3);
    const Eigen::Isometry3d X = Translated(Home(), (reach + 0.004) * axis);  // 4 mm beyond
    r.Reset(X);
    const HapticOutput out = Hold(r, X);
    ASSERT_EQ(out.status, HapticStatus::kContact) << axis.transpose();
    EXPECT_LT(out.f_O.dot(axis), 0) << axis.transpose();
    EXPECT_GT(out.f_O.normalized().dot(InwardNormalTranslation(Rsr(), X)), 0.9);
    // The mesh depth approximates the true 4 mm (coarse atlas: 10 mm cells).
    EXPECT_NEAR(-r.last_query().translation.signed_distance, 0.004, 0.004);
  }
}

TEST_F(MeshWall, TickAllocatesNothing) {
  MeshWallRenderer r = Make();
  r.Reset(Home());
  HapticInput in;
  HapticOutput out;
  robossis::testing::AllocationCounter counter;
  for (int k = 0; k < 200; ++k) {
    in.X_OH = Translated(Home(), Eigen::Vector3d(0, 0, 0.0008 * k));
    r.Tick(in, out);
  }
  EXPECT_EQ(counter.count(), 0u);
}

// A pose 4 mm beyond the +x edge at yaw 9 deg, roll 4 deg: halfway between the coarse atlas' orientation nodes, where
// the nearest node's slice misplaces the wall.
Eigen::Isometry3d BeyondXEdgeOffNode(double beyond_m) {
  Eigen::Isometry3d turned = Home();
  turned.linear() = RotationFromRpy(Eigen::Vector3d(DegToRad(4), 0, DegToRad(9)));
  const double reach = ReachAlongAxis(Rsr(), turned, Eigen::Vector3d::UnitX(), false, 0.3);
  return Translated(turned, (reach + beyond_m) * Eigen::Vector3d::UnitX());
}

LiveBoundaryOptions CoarseLiveOptions() {
  geometry::LiveBoundaryOptions o;
  o.dexterous_resolution_m = 0.006;
  o.rotational_resolution_rad = DegToRad(3);
  return o;
}

TEST_F(MeshWall, LiveSlicesPlaceTheWallWhereTheAtlasNodeDoesNot) {
  const Eigen::Isometry3d X = BeyondXEdgeOffNode(0.004);
  MeshWallRenderer atlas_only = Make();
  atlas_only.Reset(X);
  Hold(atlas_only, X);
  MeshWallRenderer live = Make();
  live.UseLiveBoundary(std::make_shared<geometry::LiveBoundary>(Rsr(), robot::Sigma7Model::Default(),
                                                                CoarseLiveOptions()),
                       /*simulated_latency_s=*/0.1);
  live.Reset(X);
  Hold(live, X, 1);                  // posts the pose
  live.StepSimulatedBackground(0.0);  // starts a refresh at t = 0 ...
  Hold(live, X, 1);
  EXPECT_EQ(live.last_query().live_dexterous_slice, nullptr);  // ... not visible before the latency
  live.StepSimulatedBackground(0.1);
  const HapticOutput out = Hold(live, X);
  ASSERT_NE(live.last_query().live_dexterous_slice, nullptr);
  ASSERT_EQ(out.status, HapticStatus::kContact);
  // The true penetration (distance to the nearest feasible position, from the IK): the live wall is within its mesh
  // error of it, the atlas node's wall is not.
  const double truth = TranslationalPenetration(Rsr(), X);
  EXPECT_GT(truth, 0.002);
  EXPECT_NEAR(-live.last_query().translation.signed_distance, truth, 0.0005);
  EXPECT_GT(std::abs(-atlas_only.last_query().translation.signed_distance - truth), 0.002);
  EXPECT_GT(out.f_O.normalized().dot(InwardNormalTranslation(Rsr(), X)), 0.9);
}

TEST_F(MeshWall, LiveTickAllocatesNothing) {
  MeshWallRenderer r = Make();
  r.UseLiveBoundary(std::make_shared<geometry::LiveBoundary>(Rsr(), robot::Sigma7Model::Default(),
                                                             CoarseLiveOptions()),
                    0.0);
  const Eigen::Isometry3d X = BeyondXEdgeOffNode(0.002);
  r.Reset(X);
  Hold(r, X, 1);
  r.StepSimulatedBackground(0.0);
  r.StepSimulatedBackground(0.0);  // latency 0: published on the next step
  HapticInput in;
  HapticOutput out;
  in.X_OH = X;
  r.Tick(in, out);
  ASSERT_NE(r.last_query().live_dexterous_slice, nullptr);
  robossis::testing::AllocationCounter counter;
  for (int k = 0; k < 200; ++k) {
    in.X_OH = Translated(X, Eigen::Vector3d(0, 0, 2e-5 * k));
    r.Tick(in, out);
  }
  EXPECT_EQ(counter.count(), 0u);
}

TEST(SliceSwitchBlend, TakesUpASlicesJumpLinearly) {
  SliceSwitchBlend blend;
  blend.Configure(4);
  const int a = 0, b = 0;  // two slice identities
  EXPECT_TRUE(blend.Apply(&a, Eigen::Vector3d(1, 0, 0)).isApprox(Eigen::Vector3d(1, 0, 0)));  // first: no blend
  EXPECT_TRUE(blend.Apply(&a, Eigen::Vector3d(2, 0, 0)).isApprox(Eigen::Vector3d(2, 0, 0)));  // same slice
  // Switch: the new slice says 6; the rendered value starts at the old 2 and reaches 6 after 4 ticks.
  std::vector<double> seen;
  for (int k = 0; k < 6; ++k) seen.push_back(blend.Apply(&b, Eigen::Vector3d(6, 0, 0)).x());
  EXPECT_EQ(seen, (std::vector<double>{2, 3, 4, 5, 6, 6}));
  blend.Reset();
  EXPECT_TRUE(blend.Apply(&a, Eigen::Vector3d(0, 1, 0)).isApprox(Eigen::Vector3d(0, 1, 0)));  // no memory
}

TEST(RpyRate, MatchesFiniteDifferenceOfTheRotation) {
  const Eigen::Vector3d rpy(0.2, -0.3, 0.5), rate(0.1, 0.4, -0.2);
  const double h = 1e-7;
  const Eigen::Matrix3d R0 = RotationFromRpy(rpy), R1 = RotationFromRpy(rpy + h * rate);
  const Eigen::Vector3d w_fd = RotationVector(R1 * R0.transpose()) / h;
  EXPECT_TRUE((RpyRateToAngularVelocity(rpy) * rate).isApprox(w_fd, 1e-5));
}

}  // namespace
}  // namespace robossis::haptics
