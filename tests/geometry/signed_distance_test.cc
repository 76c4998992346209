// The FCL signed penetration query.

#include "geometry/signed_distance.h"

#include <cmath>
#include <limits>
#include <optional>
#include <random>

#include <gtest/gtest.h>

#include "geometry/atlas_error.h"
#include "geometry/reference_distance.h"
#include "geometry/workspace_slice.h"
#include "src/core/units.h"
#include "tests/geometry/test_meshes.h"
#include "tests/support/alloc_counter.h"

namespace robossis::geometry {
namespace {

TEST(SignedDistanceTest, BoxDistancesMatchTheAnalyticValues) {
  const BoundaryDistanceField field(testing::BoxMesh({-1, -1, -1}, {1, 1, 1}));
  SignedDistanceQuery query;
  SignedDistanceResult r;
  // Inside, nearest face x = 1: distance 0.5 inside, outward normal +x.
  ASSERT_EQ(query.Query(&field, {0.5, 0.1, -0.2}, 0.0, &r), QueryStatus::kOk);
  EXPECT_NEAR(r.signed_distance, 0.5, 1e-12);
  EXPECT_TRUE(r.normal.isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  EXPECT_TRUE(r.nearest.isApprox(Eigen::Vector3d(1, 0.1, -0.2), 1e-12));
  // Outside beyond an edge: distance sqrt(0.5^2 + 0.5^2), penetration = negative.
  query.Query(&field, {1.5, 1.5, 0}, 0.0, &r);
  EXPECT_NEAR(r.signed_distance, -std::sqrt(0.5), 1e-12);
  EXPECT_TRUE(r.normal.isApprox(Eigen::Vector3d(1, 1, 0).normalized(), 1e-12));
  // Outside beyond a vertex.
  query.Query(&field, {2, 2, 2}, 0.0, &r);
  EXPECT_NEAR(r.signed_distance, -std::sqrt(3.0), 1e-12);
}

TEST(SignedDistanceTest, SphereRadiusIsSubtracted) {
  const BoundaryDistanceField field(testing::BoxMesh({-1, -1, -1}, {1, 1, 1}));
  SignedDistanceQuery query;
  SignedDistanceResult r;
  query.Query(&field, {0.9, 0, 0}, 0.3, &r);
  EXPECT_NEAR(r.signed_distance, 0.1 - 0.3, 1e-12);  // the sphere sticks out by 0.2
  EXPECT_TRUE(r.inside);
}

TEST(SignedDistanceTest, SignAgreesWithTheSphereOnRandomPoints) {
  // Icosphere of radius 1 (vertices on the sphere): inside exactly when |q| < 1 away from the chord gap.
  const BoundaryDistanceField field(testing::IcoSphere(3, 1.0));
  SignedDistanceQuery query;
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> u(-1.6, 1.6);
  int wrong = 0;
  for (int n = 0; n < 5000; ++n) {
    const Eigen::Vector3d q(u(gen), u(gen), u(gen));
    if (std::abs(q.norm() - 1.0) < 0.02) continue;  // chord error of level-3 icosphere < 0.02
    SignedDistanceResult r;
    query.Query(&field, q, 0.0, &r);
    wrong += (r.signed_distance > 0) != (q.norm() < 1.0) ? 1 : 0;
    EXPECT_NEAR(r.signed_distance, 1.0 - q.norm(), 0.02);
  }
  EXPECT_EQ(wrong, 0);
}

TEST(SignedDistanceTest, WarmStartedQueriesEqualColdOnes) {
  // A reused query object seeds FCL with the previous closest triangle; the answer must not change.
  const BoundaryDistanceField field(testing::IcoSphere(3, 1.0));
  SignedDistanceQuery warm;
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  Eigen::Vector3d q(0.5, 0.5, 0.5);
  for (int n = 0; n < 500; ++n) {
    q += 0.05 * Eigen::Vector3d(u(gen), u(gen), u(gen));  // a wandering point, like a haptic handle
    q = q.cwiseMax(-1.5).cwiseMin(1.5);
    SignedDistanceQuery cold;
    SignedDistanceResult a, b;
    warm.Query(&field, q, 0.0, &a);
    cold.Query(&field, q, 0.0, &b);
    EXPECT_NEAR(a.signed_distance, b.signed_distance, 1e-12);
  }
}

TEST(SignedDistanceTest, WarmStartIsNotFooledByAFieldRebuiltAtTheSameAddress) {
  // A refreshed slice may be built where the previous one was freed; the warm start must not reuse the old
  // triangle index (the icosphere has 1280 triangles, the box 12).
  std::optional<BoundaryDistanceField> field;
  field.emplace(testing::IcoSphere(3, 1.0));
  SignedDistanceQuery query;
  SignedDistanceResult r;
  query.Query(&*field, {0.1, 0.2, 1.3}, 0.0, &r);
  ASSERT_GT(r.triangle, 12);
  field.reset();
  field.emplace(testing::BoxMesh({-1, -1, -1}, {1, 1, 1}));
  ASSERT_EQ(query.Query(&*field, {0.1, 0.2, 1.3}, 0.0, &r), QueryStatus::kOk);
  EXPECT_NEAR(r.signed_distance, -0.3, 1e-12);
}

TEST(SignedDistanceTest, InsideCutoffSkipsOnlyWhatCannotBeNearTheBoundary) {
  // A wandering point inside and outside a unit sphere: with the cutoff, the side always matches the exact query,
  // exact distances are unchanged, and a skipped search only happens where the boundary is beyond the cutoff.
  const BoundaryDistanceField field(testing::IcoSphere(3, 1.0));
  SignedDistanceQuery exact, cut;
  cut.set_inside_cutoff(0.2);
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Vector3d q = Eigen::Vector3d::Zero();
  int skipped = 0;
  for (int n = 0; n < 3000; ++n) {
    q += 0.02 * Eigen::Vector3d(u(gen), u(gen), u(gen));
    q = q.cwiseMax(-1.3).cwiseMin(1.3);
    SignedDistanceResult a, b;
    exact.Query(&field, q, 0.0, &a);
    cut.Query(&field, q, 0.0, &b);
    ASSERT_EQ(a.inside, b.inside) << n;
    if (b.beyond_inside_cutoff) {
      ++skipped;
      EXPECT_GE(a.signed_distance, 0.2 - 1e-12);
      EXPECT_DOUBLE_EQ(b.signed_distance, 0.2);
    } else {
      EXPECT_DOUBLE_EQ(a.signed_distance, b.signed_distance);
    }
  }
  EXPECT_GT(skipped, 300);  // the walk spends much of its time deep inside
}

TEST(SignedDistanceTest, BadInputsGiveAStatus) {
  const BoundaryDistanceField field(testing::BoxMesh({-1, -1, -1}, {1, 1, 1}));
  SignedDistanceQuery query;
  SignedDistanceResult r;
  EXPECT_EQ(query.Query(nullptr, {0, 0, 0}, 0.0, &r), QueryStatus::kNoField);
  EXPECT_EQ(query.Query(&field, {std::nan(""), 0, 0}, 0.0, &r), QueryStatus::kNonFinite);
  EXPECT_EQ(query.Query(&field, {0, 0, 0}, -1.0, &r), QueryStatus::kNonFinite);
}

TEST(SignedDistanceTest, OpenMeshIsRejected) {
  TriangleMesh open = testing::BoxMesh({-1, -1, -1}, {1, 1, 1});
  open.triangles.pop_back();
  EXPECT_THROW(BoundaryDistanceField field(open), std::invalid_argument);
}

TEST(SignedDistanceTest, QueryAllocatesNothing) {
  const BoundaryDistanceField field(testing::IcoSphere(3, 1.0));
  SignedDistanceQuery query;
  SignedDistanceResult r;
  query.Query(&field, {0.1, 0.2, 0.3}, 0.0, &r);  // warm-up
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  std::vector<Eigen::Vector3d> points;
  for (int n = 0; n < 200; ++n) points.emplace_back(u(gen), u(gen), u(gen));
  robossis::testing::AllocationCounter counter;
  for (const Eigen::Vector3d& q : points) query.Query(&field, q, 0.001, &r);
  EXPECT_EQ(counter.count(), 0u);
}

class SliceQueryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    slice_ = GenerateSlice(rsr_, hc_, {SliceKind::kRsrDexterous, {0, DegToRad(5), DegToRad(10)}, 0.006});
  }
  robot::RsrModel rsr_ = robot::RsrModel::Default();
  robot::Sigma7Model hc_ = robot::Sigma7Model::Default();
  WorkspaceSlice slice_;
};

TEST_F(SliceQueryTest, SignAgreesWithIkOnRandomPointsNearTheBoundary) {
  const BoundaryDistanceField field(slice_.mesh);
  const SliceFeasibility f(rsr_, hc_, slice_.spec.kind, slice_.spec.fixed);
  SignedDistanceQuery query;
  std::mt19937 gen{42};
  std::uniform_int_distribution<std::size_t> pick(0, slice_.mesh.vertices.size() - 1);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  int tested = 0, wrong = 0;
  for (int n = 0; n < 3000; ++n) {
    const Eigen::Vector3d q = slice_.mesh.vertices[pick(gen)] + Eigen::Vector3d(u(gen), u(gen), u(gen));
    SignedDistanceResult r;
    query.Query(&field, q, 0.0, &r);
    if (std::abs(r.signed_distance) < slice_.spec.resolution) continue;  // the mesh's chord band
    ++tested;
    wrong += (r.signed_distance > 0) != f(q) ? 1 : 0;
  }
  EXPECT_GT(tested, 1000);
  EXPECT_EQ(wrong, 0);
}

TEST_F(SliceQueryTest, NearestDistanceIsTheMinimumOverAllTriangles) {
  // The tree search must find the global minimum: compare with a brute-force scan of every triangle, for points
  // near and far (up to 0.3 m) from the boundary, with a warm-started query object.
  const BoundaryDistanceField field(slice_.mesh);
  const auto& V = field.mesh().vertices;
  SignedDistanceQuery query;
  std::mt19937 gen{42};
  std::uniform_int_distribution<std::size_t> pick(0, V.size() - 1);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n = 0; n < 200; ++n) {
    const double spread = n % 2 == 0 ? 0.01 : 0.3;
    const Eigen::Vector3d q = V[pick(gen)] + spread * Eigen::Vector3d(u(gen), u(gen), u(gen));
    double brute = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3i& t : field.mesh().triangles) {
      brute = std::min(brute, testing::PointTriangleDistance(q, V[t[0]], V[t[1]], V[t[2]]));
    }
    SignedDistanceResult r;
    ASSERT_EQ(query.Query(&field, q, 0.0, &r), QueryStatus::kOk);
    EXPECT_NEAR(std::abs(r.signed_distance), brute, 1e-12) << "point " << n;
  }
}

TEST_F(SliceQueryTest, AgreesWithTheIndependentReferenceDistance) {
  // The reference uses only IK (ray casting + local minimisation), never the mesh.
  const ErrorStats e = MeasureSliceError(rsr_, hc_, slice_, 15, 42);
  EXPECT_EQ(e.samples + e.not_found, 15);
  EXPECT_GE(e.samples, 12);
  EXPECT_LT(e.p50, 0.5e-3);  // the mesh error of a 6 mm grid: chord error (README, "Accuracy")
  EXPECT_LT(e.max, 3e-3);
}

TEST(ReferenceDistanceTest, MatchesTheAnalyticSphere) {
  const FeasibilityFn ball = [](const Eigen::Vector3d& q) { return q.norm() <= 0.05; };
  ReferenceDistanceOptions o;
  o.max_distance = 0.1;
  o.directions = 200;
  const ReferenceDistanceResult in = ComputeReferenceSignedDistance(ball, {0.01, 0.02, 0}, o);
  ASSERT_TRUE(in.found);
  EXPECT_NEAR(in.signed_distance, 0.05 - std::hypot(0.01, 0.02), 1e-6);
  const ReferenceDistanceResult out = ComputeReferenceSignedDistance(ball, {0.07, 0, 0}, o);
  EXPECT_NEAR(out.signed_distance, -0.02, 1e-6);
}

}  // namespace
}  // namespace robossis::geometry
