// Workspace slices and their boundary meshes.

#include "geometry/workspace_slice.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "geometry/signed_distance.h"
#include "robot/rsr_kinematics.h"
#include "src/core/pose.h"
#include "src/core/units.h"

namespace robossis::geometry {
namespace {

class SliceTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    rsr_ = new robot::RsrModel(robot::RsrModel::Default());
    hc_ = new robot::Sigma7Model(robot::Sigma7Model::Default());
    // Coarse grids keep the suite fast (also under the sanitizers); the properties hold at any resolution.
    dexterous_ = new WorkspaceSlice(GenerateSlice(*rsr_, *hc_, {SliceKind::kRsrDexterous, {0, 0, 0}, 0.008}));
    rotational_ = new WorkspaceSlice(GenerateSlice(
        *rsr_, *hc_, {SliceKind::kRsrRotational, rsr_->geometry().X_FM_home.translation(), DegToRad(3)}));
  }
  static void TearDownTestSuite() {
    delete dexterous_;
    delete rotational_;
    delete rsr_;
    delete hc_;
  }
  static robot::RsrModel* rsr_;
  static robot::Sigma7Model* hc_;
  static WorkspaceSlice* dexterous_;
  static WorkspaceSlice* rotational_;
};
robot::RsrModel* SliceTest::rsr_ = nullptr;
robot::Sigma7Model* SliceTest::hc_ = nullptr;
WorkspaceSlice* SliceTest::dexterous_ = nullptr;
WorkspaceSlice* SliceTest::rotational_ = nullptr;

// Every vertex has the boundary within `h`: along some axis, q - h e and q + h e differ in feasibility.
void ExpectVerticesOnBoundary(const WorkspaceSlice& slice, const SliceFeasibility& f, double h) {
  int off = 0;
  for (const Eigen::Vector3d& v : slice.mesh.vertices) {
    bool on = false;
    for (int a = 0; a < 3 && !on; ++a) {
      on = f(v + h * Eigen::Vector3d::Unit(a)) != f(v - h * Eigen::Vector3d::Unit(a));
    }
    off += on ? 0 : 1;
  }
  EXPECT_EQ(off, 0) << "vertices farther than " << h << " from the boundary";
}

TEST_F(SliceTest, DexterousMeshIsWatertightAndOutward) {
  EXPECT_TRUE(dexterous_->stats.watertight);
  EXPECT_TRUE(dexterous_->stats.outward);
  EXPECT_GT(dexterous_->stats.volume, 0);
}

TEST_F(SliceTest, RotationalMeshIsWatertightAndOutward) {
  EXPECT_TRUE(rotational_->stats.watertight);
  EXPECT_TRUE(rotational_->stats.outward);
}

TEST_F(SliceTest, DexterousVerticesLieWithinOneHundredthMmOfTheBoundary) {
  // Within 0.01 mm of the true boundary at any grid resolution.
  ExpectVerticesOnBoundary(*dexterous_, SliceFeasibility(*rsr_, *hc_, SliceKind::kRsrDexterous, {0, 0, 0}), 1e-5);
}

TEST_F(SliceTest, RotationalVerticesLieWithinOneHundredthDegreeOfTheBoundary) {
  ExpectVerticesOnBoundary(*rotational_,
                           SliceFeasibility(*rsr_, *hc_, SliceKind::kRsrRotational, rotational_->spec.fixed),
                           DegToRad(0.01));
}

// Random points more than one voxel from the mesh are inside the mesh exactly when IK says feasible.
void ExpectMeshAgreesWithIk(const WorkspaceSlice& slice, const SliceFeasibility& f) {
  const BoundaryDistanceField field(slice.mesh);
  SignedDistanceQuery query;
  std::mt19937 gen{42};
  const Eigen::Vector3d lo = slice.stats.min, hi = slice.stats.max, pad = 0.2 * (hi - lo);
  int tested = 0, disagree = 0;
  for (int n = 0; n < 3000; ++n) {
    Eigen::Vector3d q;
    for (int a = 0; a < 3; ++a) q[a] = std::uniform_real_distribution<double>(lo[a] - pad[a], hi[a] + pad[a])(gen);
    SignedDistanceResult r;
    ASSERT_EQ(query.Query(&field, q, 0.0, &r), QueryStatus::kOk);
    if (std::abs(r.signed_distance) <= slice.spec.resolution) continue;
    ++tested;
    disagree += (r.signed_distance > 0) != f(q) ? 1 : 0;
  }
  EXPECT_GT(tested, 1000);
  EXPECT_EQ(disagree, 0);
}

TEST_F(SliceTest, DexterousMeshInsideExactlyWhenIkFeasible) {
  ExpectMeshAgreesWithIk(*dexterous_, SliceFeasibility(*rsr_, *hc_, SliceKind::kRsrDexterous, {0, 0, 0}));
}

TEST_F(SliceTest, RotationalMeshInsideExactlyWhenIkFeasible) {
  ExpectMeshAgreesWithIk(*rotational_,
                         SliceFeasibility(*rsr_, *hc_, SliceKind::kRsrRotational, rotational_->spec.fixed));
}

TEST_F(SliceTest, DexterousSliceAtIdentityIsInvariantUnder120DegreesAboutTheAxis) {
  // The arms sit at -30, 90, 210 deg about the z axis of F (paper §III-B): rotating a position by 120 deg about that
  // axis permutes the arms. The mesh's signed distance must agree at p and Rz(120) p up to the mesh's own error.
  const BoundaryDistanceField field(dexterous_->mesh);
  SignedDistanceQuery query;
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(DegToRad(120), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::mt19937 gen{42};
  std::uniform_int_distribution<std::size_t> pick(0, dexterous_->mesh.vertices.size() - 1);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  double worst = 0;
  for (int n = 0; n < 300; ++n) {
    const Eigen::Vector3d p = dexterous_->mesh.vertices[pick(gen)] + Eigen::Vector3d(u(gen), u(gen), u(gen));
    SignedDistanceResult a, b;
    query.Query(&field, p, 0.0, &a);
    query.Query(&field, Rz * p, 0.0, &b);
    worst = std::max(worst, std::abs(a.signed_distance - b.signed_distance));
  }
  // Tolerance: the chord error of an 8 mm grid on this boundary (measured below 2 mm; see README).
  EXPECT_LT(worst, 0.003);
  // And the feasibility itself is exactly symmetric.
  const SliceFeasibility f(*rsr_, *hc_, SliceKind::kRsrDexterous, {0, 0, 0});
  for (int n = 0; n < 2000; ++n) {
    const Eigen::Vector3d p = dexterous_->mesh.vertices[pick(gen)] + Eigen::Vector3d(u(gen), u(gen), u(gen));
    EXPECT_EQ(f(p), f(Rz * p));
  }
}

TEST_F(SliceTest, VolumeConvergesAsTheResolutionIsRefined) {
  std::vector<double> volumes;
  for (double h : {0.016, 0.008, 0.004}) {
    volumes.push_back(GenerateSlice(*rsr_, *hc_, {SliceKind::kRsrDexterous, {0, 0, 0}, h}).stats.volume);
  }
  const double d1 = std::abs(volumes[1] - volumes[0]), d2 = std::abs(volumes[2] - volumes[1]);
  EXPECT_LT(d2, d1);
  EXPECT_LT(d2 / volumes[2], 0.01);
}

TEST_F(SliceTest, HcSlicesAreClosedAndTheWristIsTheRangeBox) {
  const WorkspaceSlice t = GenerateSlice(*rsr_, *hc_, {SliceKind::kHcTranslation, {0, 0, 0}, 0.008});
  EXPECT_TRUE(t.stats.watertight);
  EXPECT_TRUE(t.stats.outward);
  const WorkspaceSlice w = GenerateSlice(*rsr_, *hc_, {SliceKind::kHcWrist, {0, 0, 0}, DegToRad(5)});
  EXPECT_TRUE(w.stats.watertight);
  EXPECT_TRUE(w.stats.outward);
  // Paper §III-C: 235 x 140 x 200 deg (sigma7.yaml: yaw, pitch, roll). The extents are exact (vertices refined onto
  // the faces); the volume misses only the chamfered edges and corners of the marching-cubes surface.
  const Eigen::Vector3d size = (w.stats.max - w.stats.min) * kRadToDeg;
  EXPECT_NEAR(size.x(), 200, 0.01);
  EXPECT_NEAR(size.y(), 140, 0.01);
  EXPECT_NEAR(size.z(), 235, 0.01);
  const double box = DegToRad(200) * DegToRad(140) * DegToRad(235);
  EXPECT_NEAR(w.stats.volume / box, 1.0, 0.03);
}

// The dexterous grid tests only the nodes its rows' bounds leave (DexterousRowBounds): the grid must be the one that
// testing every node gives, at the live slices' 4 mm and orientations over the workspace's tilt and twist.
TEST_F(SliceTest, DexterousGridIsTheOneEveryNodeTestedGives) {
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> tilt(-DegToRad(20), DegToRad(20));
  std::uniform_real_distribution<double> twist(-DegToRad(40), DegToRad(40));
  int compared = 0;
  for (int n = 0; n < 12; ++n) {
    const Eigen::Vector3d rpy(tilt(gen), tilt(gen), twist(gen));
    WorkspaceSlice slice;
    try {
      slice = GenerateSlice(*rsr_, *hc_, {SliceKind::kRsrDexterous, rpy, 0.004});
    } catch (const std::runtime_error&) {
      continue;  // unreachable orientation: no grid to compare
    }
    const SliceFeasibility feasible(*rsr_, *hc_, SliceKind::kRsrDexterous, rpy);
    const VoxelGrid& g = slice.grid;
    std::size_t differ = 0, nodes_feasible = 0;
    for (int k = 0; k < g.dims.z(); ++k) {
      for (int j = 0; j < g.dims.y(); ++j) {
        for (int i = 0; i < g.dims.x(); ++i) {
          const bool exact = feasible(g.Node(i, j, k));
          nodes_feasible += exact;
          differ += exact != (g.feasible[g.Index(i, j, k)] == 1);
        }
      }
    }
    EXPECT_EQ(differ, 0u) << "rpy (deg) " << (rpy * kRadToDeg).transpose();
    EXPECT_EQ(nodes_feasible, slice.feasible_nodes);
    ++compared;
  }
  EXPECT_GE(compared, 8);
}

TEST_F(SliceTest, DexterousGridSkipsMostNodesNoArmReaches) {
  const std::size_t nodes = dexterous_->grid.feasible.size();
  EXPECT_GE(dexterous_->grid_evaluations, dexterous_->feasible_nodes);
  EXPECT_LT(dexterous_->grid_evaluations, nodes / 2) << dexterous_->grid_evaluations << " of " << nodes;
}

TEST_F(SliceTest, NonPositiveResolutionIsRejected) {
  for (double h : {0.0, -0.002, std::nan("")}) {
    EXPECT_THROW(GenerateSlice(*rsr_, *hc_, {SliceKind::kRsrDexterous, {0, 0, 0}, h}), std::invalid_argument);
  }
}

TEST_F(SliceTest, UnreachableSlicePoseGivesAClearError) {
  try {
    GenerateSlice(*rsr_, *hc_, {SliceKind::kRsrDexterous, {DegToRad(80), 0, 0}, 0.008});
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
  }
  EXPECT_THROW(GenerateSlice(*rsr_, *hc_, {SliceKind::kRsrRotational, {0, 0, 1.0}, DegToRad(3)}), std::runtime_error);
}

}  // namespace
}  // namespace robossis::geometry
