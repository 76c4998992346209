// The live boundary: slices regenerated at the current pose, published to the real-time thread without locks.

#include "geometry/live_boundary.h"

#include <chrono>
#include <random>
#include <thread>

#include <gtest/gtest.h>

#include "geometry/atlas_error.h"
#include "src/core/pose.h"
#include "src/core/units.h"
#include "tests/support/alloc_counter.h"

namespace robossis::geometry {
namespace {

// Coarse live slices keep the tests fast; the tolerances are the defaults.
LiveBoundaryOptions FastOptions() {
  LiveBoundaryOptions o;
  o.dexterous_resolution_m = 0.008;
  o.rotational_resolution_rad = DegToRad(4);
  return o;
}

class LiveBoundaryTest : public ::testing::Test {
 protected:
  // A one-node atlas at the home pose: its slices are the fallback the live ones must beat off that node.
  static void SetUpTestSuite() {
    const robot::RsrModel& rsr = Rsr();
    const Eigen::Vector3d home = rsr.geometry().X_FM_home.translation();
    AtlasSpec spec;
    spec.orientation_grid = {GridAxis{0, 1, 1}, GridAxis{0, 1, 1}, GridAxis{0, 1, 1}};
    spec.position_grid = {GridAxis{home.x(), 1, 1}, GridAxis{home.y(), 1, 1}, GridAxis{home.z(), 1, 1}};
    spec.dexterous_resolution_m = 0.008;
    spec.rotational_resolution_rad = DegToRad(4);
    auto slice = [&](SliceKind kind, const Eigen::Vector3d& fixed, double resolution) {
      AtlasSlice s;
      s.kind = kind;
      s.fixed = fixed;
      s.field = std::make_shared<BoundaryDistanceField>(GenerateSlice(rsr, Hc(), {kind, fixed, resolution}).mesh);
      return s;
    };
    atlas_ = new BoundaryAtlas(spec, {slice(SliceKind::kRsrDexterous, Eigen::Vector3d::Zero(), 0.008)},
                               {slice(SliceKind::kRsrRotational, home, DegToRad(4))});
  }
  static void TearDownTestSuite() { delete atlas_; }
  static const robot::RsrModel& Rsr() {
    static const robot::RsrModel rsr = robot::RsrModel::Default();
    return rsr;
  }
  static const robot::Sigma7Model& Hc() {
    static const robot::Sigma7Model hc = robot::Sigma7Model::Default();
    return hc;
  }
  // A pose 30 mm off home, turned 6 deg in yaw and 3 deg in roll: far from the atlas node in both families.
  static Eigen::Isometry3d OffNodePose() {
    return PoseFromPositionRpy(Rsr().geometry().X_FM_home.translation() + Eigen::Vector3d(0.03, 0, 0),
                               Eigen::Vector3d(DegToRad(3), 0, DegToRad(6)));
  }
  static BoundaryAtlas* atlas_;
};
BoundaryAtlas* LiveBoundaryTest::atlas_ = nullptr;

// Count of random points (near the live slice's boundary, beyond the mesh's chord band) where the query's sign
// disagrees with the IK at the actual pose.
// `field` supplies the sample points; `queried` answers.
int SignDisagreements(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, const BoundaryDistanceField& field,
                      SliceKind kind, const Eigen::Vector3d& fixed, const BoundaryDistanceField* queried, double band) {
  const SliceFeasibility truth(rsr, hc, kind, fixed);
  SignedDistanceQuery query;
  std::mt19937 gen{42};
  std::uniform_int_distribution<std::size_t> pick(0, field.mesh().vertices.size() - 1);
  std::uniform_real_distribution<double> u(-3 * band, 3 * band);
  int wrong = 0;
  for (int n = 0; n < 400; ++n) {
    const Eigen::Vector3d q = field.mesh().vertices[pick(gen)] + Eigen::Vector3d(u(gen), u(gen), u(gen));
    SignedDistanceResult r;
    query.Query(queried, q, 0.0, &r);
    if (std::abs(r.signed_distance) < band) continue;
    wrong += (r.signed_distance > 0) != truth(q) ? 1 : 0;
  }
  return wrong;
}

TEST_F(LiveBoundaryTest, RefreshPublishesSlicesAtThePostedPoseAndTheQueryPrefersThem) {
  LiveBoundary live(Rsr(), Hc(), FastOptions());
  LivePoseQuery query;
  PoseBoundaryResult r;
  const Eigen::Isometry3d X = OffNodePose();
  query.Query(live, atlas_, X, 0, 0, &r);  // posts the pose; nothing live yet: the atlas answers
  EXPECT_EQ(r.live_dexterous_slice, nullptr);
  ASSERT_NE(r.dexterous_slice, nullptr);
  EXPECT_EQ(live.RefreshNow(), 2);
  query.Query(live, atlas_, X, 0, 0, &r);
  ASSERT_NE(r.live_dexterous_slice, nullptr);
  ASSERT_NE(r.live_rotational_slice, nullptr);
  EXPECT_TRUE(r.live_dexterous_slice->fixed.isApprox(RpyFromRotation(X.linear()), 1e-12));
  EXPECT_TRUE(r.live_rotational_slice->fixed.isApprox(X.translation(), 1e-12));
  EXPECT_EQ(r.translation.status, QueryStatus::kOk);
  EXPECT_EQ(r.rotation.status, QueryStatus::kOk);
}

TEST_F(LiveBoundaryTest, LiveSliceAgreesWithIkWhereTheAtlasNodeDoesNot) {
  // At the off-node pose the atlas' home slices put the boundary in the wrong place; the live slices do not.
  LiveBoundary live(Rsr(), Hc(), FastOptions());
  const Eigen::Isometry3d X = OffNodePose();
  live.PostPose(X);
  ASSERT_EQ(live.RefreshNow(), 2);
  const LiveSlice* dexterous = live.AcquireDexterous();
  ASSERT_NE(dexterous, nullptr);
  const Eigen::Vector3d rpy = RpyFromRotation(X.linear());
  const int live_wrong =
      SignDisagreements(Rsr(), Hc(), *dexterous->field, SliceKind::kRsrDexterous, rpy, dexterous->field.get(), 0.008);
  const int atlas_wrong = SignDisagreements(Rsr(), Hc(), *dexterous->field, SliceKind::kRsrDexterous, rpy,
                                            atlas_->dexterous()[0].field.get(), 0.008);
  EXPECT_EQ(live_wrong, 0);
  EXPECT_GT(atlas_wrong, 20);
}

TEST_F(LiveBoundaryTest, RefreshesOnlyTheFamilyWhosePoseMovedBeyondTheTolerance) {
  LiveBoundary live(Rsr(), Hc(), FastOptions());
  const Eigen::Vector3d p = Rsr().geometry().X_FM_home.translation();
  live.PostPose(PoseFromPositionRpy(p, Eigen::Vector3d::Zero()));
  EXPECT_EQ(live.RefreshNow(), 2);
  EXPECT_EQ(live.RefreshNow(), 0);  // same pose: nothing to do
  // Turn by twice the orientation tolerance: the dexterous slice only.
  const double turn = 2 * live.options().orientation_tolerance_rad;
  live.PostPose(PoseFromPositionRpy(p, Eigen::Vector3d(0, 0, turn)));
  EXPECT_EQ(live.RefreshNow(), 1);
  EXPECT_NEAR(live.AcquireDexterous()->fixed.z(), turn, 1e-12);
  // Move by half the position tolerance: nothing; by twice: the rotational slice only.
  live.PostPose(PoseFromPositionRpy(p + Eigen::Vector3d(0.5 * live.options().position_tolerance_m, 0, 0),
                                    Eigen::Vector3d(0, 0, turn)));
  EXPECT_EQ(live.RefreshNow(), 0);
  live.PostPose(PoseFromPositionRpy(p + Eigen::Vector3d(2 * live.options().position_tolerance_m, 0, 0),
                                    Eigen::Vector3d(0, 0, turn)));
  EXPECT_EQ(live.RefreshNow(), 1);
  EXPECT_EQ(live.published_count(), 4);
}

TEST_F(LiveBoundaryTest, AnAcquiredSliceOutlivesLaterPublications) {
  // The hazard pointer keeps the slice the real-time thread holds alive (ASan reports a use after free otherwise).
  LiveBoundary live(Rsr(), Hc(), FastOptions());
  const Eigen::Vector3d p = Rsr().geometry().X_FM_home.translation();
  live.PostPose(PoseFromPositionRpy(p, Eigen::Vector3d::Zero()));
  live.RefreshNow();
  const LiveSlice* held = live.AcquireDexterous();
  ASSERT_NE(held, nullptr);
  const std::size_t triangles = held->field->mesh().triangles.size();
  for (int k = 1; k <= 3; ++k) {
    live.PostPose(PoseFromPositionRpy(p, Eigen::Vector3d(0, 0, DegToRad(0.5 * k))));
    live.RefreshNow();
  }
  EXPECT_NE(live.AcquireRotational(), nullptr);  // the other family's hazard does not release this one
  EXPECT_EQ(held->field->mesh().triangles.size(), triangles);
  SignedDistanceQuery query;
  SignedDistanceResult r;
  EXPECT_EQ(query.Query(held->field.get(), p, 0, &r), QueryStatus::kOk);
  EXPECT_NEAR(live.AcquireDexterous()->fixed.z(), DegToRad(1.5), 1e-12);  // releases `held`
}

TEST_F(LiveBoundaryTest, UnreachablePoseKeepsThePreviousSliceAndIsNotRetried) {
  LiveBoundary live(Rsr(), Hc(), FastOptions());
  const Eigen::Vector3d p = Rsr().geometry().X_FM_home.translation();
  live.PostPose(PoseFromPositionRpy(p, Eigen::Vector3d::Zero()));
  ASSERT_EQ(live.RefreshNow(), 2);
  // A 120 deg roll is outside every joint limit: both the dexterous slice at this orientation and the rotational
  // slice 1 m away from the ring are empty.
  const Eigen::Isometry3d far = PoseFromPositionRpy(p + Eigen::Vector3d(1.0, 0, 0), Eigen::Vector3d(DegToRad(120), 0, 0));
  live.PostPose(far);
  EXPECT_EQ(live.RefreshNow(), 0);
  EXPECT_TRUE(live.AcquireDexterous()->fixed.isZero());
  Eigen::Vector3d p_now, rpy_now;
  ASSERT_TRUE(live.LatestPose(&p_now, &rpy_now));
  EXPECT_FALSE(live.NeedsRefresh(SliceKind::kRsrDexterous, p_now, rpy_now));
  EXPECT_FALSE(live.NeedsRefresh(SliceKind::kRsrRotational, p_now, rpy_now));
}

TEST_F(LiveBoundaryTest, QueryAllocatesNothing) {
  LiveBoundary live(Rsr(), Hc(), FastOptions());
  LivePoseQuery query;
  PoseBoundaryResult r;
  const Eigen::Isometry3d X = OffNodePose();
  query.Query(live, atlas_, X, 0, 0, &r);
  live.RefreshNow();
  query.Query(live, atlas_, X, 0, 0, &r);  // warm-up
  robossis::testing::AllocationCounter counter;
  for (int k = 0; k < 100; ++k) {
    query.Query(live, atlas_, PoseFromPositionRpy(X.translation() + Eigen::Vector3d(1e-5 * k, 0, 0),
                                                  RpyFromRotation(X.linear())),
                0.001, DegToRad(0.5), &r);
  }
  EXPECT_EQ(counter.count(), 0u);
}

TEST_F(LiveBoundaryTest, SimulatedRefresherPublishesAfterTheModelledLatency) {
  LiveBoundary live(Rsr(), Hc(), FastOptions());
  SimulatedRefresher refresher(live, 0.1);
  live.PostPose(OffNodePose());
  refresher.Step(0.0);  // starts a refresh from the pose at t = 0
  EXPECT_EQ(live.AcquireDexterous(), nullptr);
  refresher.Step(0.05);
  EXPECT_EQ(live.published_count(), 0);
  refresher.Step(0.1);
  EXPECT_EQ(live.published_count(), 2);
  EXPECT_NE(live.AcquireDexterous(), nullptr);
  EXPECT_THROW(SimulatedRefresher(live, -1), std::invalid_argument);
}

TEST_F(LiveBoundaryTest, BackgroundThreadFollowsTheRealTimeLoop) {
  // The real-time side posts poses and queries while the thread regenerates; every query must stay valid.
  LiveBoundary live(Rsr(), Hc(), FastOptions());
  LivePoseQuery query;
  PoseBoundaryResult r;
  const Eigen::Vector3d p = Rsr().geometry().X_FM_home.translation();
  live.Start();
  int live_answers = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  for (int k = 0; (k < 2000 || live.published_count() < 4) && std::chrono::steady_clock::now() < deadline; ++k) {
    const double a = 1e-3 * k;  // a slow circle in position and yaw
    query.Query(live, atlas_,
                PoseFromPositionRpy(p + 0.01 * Eigen::Vector3d(std::cos(a), std::sin(a), 0),
                                    Eigen::Vector3d(0, 0, DegToRad(2) * std::sin(a))),
                0, 0, &r);
    ASSERT_EQ(r.translation.status, QueryStatus::kOk);
    ASSERT_EQ(r.rotation.status, QueryStatus::kOk);
    live_answers += r.live_dexterous_slice != nullptr ? 1 : 0;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  live.Stop();
  EXPECT_GE(live.published_count(), 4);
  EXPECT_GT(live_answers, 0);
}

TEST(LiveBoundaryOptionsTest, InvalidOptionsAreRejectedNamingTheField) {
  LiveBoundaryOptions o;
  o.position_tolerance_m = 0;
  try {
    o.Validate();
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("position_tolerance_m"), std::string::npos);
  }
}

TEST(LiveErrorTest, StaleLiveSlicesStayWithinTheBudgetAtClinicalSpeeds) {
  // Staleness of a live slice at the clinical speeds (2 mm/s, 0.2 deg/s) over a 0.25 s refresh, plus the refresh
  // tolerances: 0.05 deg + 0.025 deg of orientation, 0.5 mm + 0.5 mm of position. The error against the true
  // boundary at the actual pose must stay below 0.5 mm / 0.5 deg (issue: atlas accuracy target) at the median.
  const robot::RsrModel rsr = robot::RsrModel::Default();
  const robot::Sigma7Model hc = robot::Sigma7Model::Default();
  LiveErrorOptions o;
  o.samples = 6;
  o.orientation_staleness_rad = DegToRad(0.075);
  o.position_staleness_m = 0.001;
  const LiveErrorReport e = MeasureLiveError(rsr, hc, AtlasSpec::Coarse(rsr), FastOptions(), o);
  EXPECT_GE(e.dexterous.samples, 4);
  EXPECT_GE(e.rotational.samples, 4);
  EXPECT_LT(e.dexterous.p50, 0.5e-3);
  EXPECT_LT(e.rotational.p50, DegToRad(0.5));
}

}  // namespace
}  // namespace robossis::geometry
