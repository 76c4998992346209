// End-to-end on synthetic Motive takes whose ground truth is known (the goals): clock offset ≤ 1 ms,
// transform ≤ 0.05 mm / 0.01°, injected mean error within 0.01 mm.

#include "calibration/tracking_eval.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "calibration/synthetic_tracker.h"
#include "calibration/tracking_report.h"
#include "tests/calibration/test_support.h"

namespace robossis::calibration {
namespace {

using ::testing::HasSubstr;

struct Session {
  SyntheticTrackerOptions tracker;
  PoseTrajectory commanded, actual;
  TrackingEvalResult result;
  double true_mean_error_m = 0;
};

// The ring follows the commanded motion plus a known error (a 1.3 Hz oscillation, not a rigid transform, so the
// registration cannot absorb it); the tracker records it through an unknown placement, offset and clock.
Session RunSession(double error_amplitude_m, int gaps, double drift) {
  Session s;
  s.commanded = testing::TestMotion(40.0);
  double sum = 0;
  for (std::size_t i = 0; i < s.commanded.size(); ++i) {
    const double t = s.commanded.t_s[i];
    const Eigen::Vector3d e(0.3 * std::sin(2 * kPi * 1.3 * t), 0.0, std::cos(2 * kPi * 1.3 * t));
    const Eigen::Vector3d err = error_amplitude_m * e;
    s.actual.Add(t, s.commanded.p[i] + err, s.commanded.q[i]);
    sum += err.norm();
  }
  s.true_mean_error_m = sum / static_cast<double>(s.commanded.size());
  s.tracker.X_TF = PoseFromMmDeg((Vector6d() << 350, -420, 1650, 178, -3, 35).finished());
  s.tracker.X_MB = PoseFromMmDeg((Vector6d() << 12, -8, 30, 2, -1, 40).finished());
  s.tracker.clock_offset_s = 7.3421;
  s.tracker.clock_drift = drift;
  s.tracker.occlusion_gaps = gaps;
  MotiveReader reader(testing::WriteTake(s.actual, s.tracker), "synthetic.csv");
  const RigidBodyTrack track = ReadRigidBodyTrack(reader, s.tracker.rigid_body_name);
  s.result = EvaluateTracking(track, s.commanded);
  return s;
}

class TrackingEvalTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { session_ = new Session(RunSession(0.2e-3, 4, 20e-6)); }
  static void TearDownTestSuite() { delete session_; }
  static Session* session_;
};
Session* TrackingEvalTest::session_ = nullptr;

TEST_F(TrackingEvalTest, RecoversClockOffsetWithinOneMillisecond) {
  EXPECT_NEAR(session_->result.clock.offset_s, session_->tracker.clock_offset_s, 1e-3);
}

TEST_F(TrackingEvalTest, RecoversTrackerTransformWithinTolerance) {
  const Eigen::Isometry3d X_FT_true = session_->tracker.X_TF.inverse();
  const HandEyeResult& r = session_->result.registration;
  // Judged in the workspace (ring home), where the transform is used; see registration_test.cc.
  const Eigen::Vector3d p_F_home(0, 0, 0.284);
  EXPECT_LT((r.X_FT * (X_FT_true.inverse() * p_F_home) - p_F_home).norm(), 0.05e-3);
  EXPECT_LT(RotationAngleBetween(r.X_FT.linear(), X_FT_true.linear()), DegToRad(0.01));
}

TEST_F(TrackingEvalTest, RecoversMarkerOffsetWithinTolerance) {
  const HandEyeResult& r = session_->result.registration;
  EXPECT_LT((r.X_MB.translation() - session_->tracker.X_MB.translation()).norm(), 0.05e-3);
  EXPECT_LT(RotationAngleBetween(r.X_MB.linear(), session_->tracker.X_MB.linear()), DegToRad(0.01));
}

TEST_F(TrackingEvalTest, RecoversInjectedMeanErrorWithinOneHundredthMm) {
  EXPECT_NEAR(session_->result.translation.mean, session_->true_mean_error_m, 0.01e-3);
}

TEST_F(TrackingEvalTest, ExcludesOccludedFramesAndReportsGaps) {
  const TrackingEvalResult& r = session_->result;
  EXPECT_EQ(r.gaps.gaps, 4);
  EXPECT_GT(r.excluded.missing, 0u);
  EXPECT_GT(r.excluded.outside_reference, 0u);  // 1 s lead-in and lead-out
  EXPECT_EQ(r.excluded.orientation_flip, 0u);
  EXPECT_EQ(r.translation.count + r.excluded.total(), r.frames_total);
  EXPECT_GT(r.quaternion_sign_flips, 0);  // the synthetic tracker negates q every 97 frames
}

TEST_F(TrackingEvalTest, SummaryJsonHasTheIssueKeys) {
  const nlohmann::ordered_json j = TrackingSummaryJson(session_->result);
  for (const char* group : {"translation_error_mm", "rotation_error_deg"}) {
    for (const char* key : {"mean", "median", "rmse", "p95", "max"}) EXPECT_TRUE(j[group].contains(key)) << key;
    for (const char* axis : {"x", "y", "z"}) EXPECT_TRUE(j[group]["per_axis"].contains(axis));
  }
  for (const char* key : {"time_offset_s", "registration_rms_mm", "frames_used", "frames_excluded"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_NEAR(j["translation_error_mm"]["mean"].get<double>(), session_->result.translation.mean * 1e3, 1e-12);
}

TEST(TrackingEvalStandaloneTest, OrientationFlipsAreExcluded) {
  const PoseTrajectory commanded = testing::TestMotion(20.0);
  SyntheticTrackerOptions o;
  std::string take = testing::WriteTake(commanded, o);
  // Corrupt 5 consecutive frames' quaternions into a 180° flip about x (a marker mislabelling): q → (w,x,y,z)·(0,1,0,0).
  MotiveReader reader(take, "flip.csv");
  RigidBodyTrack track = ReadRigidBodyTrack(reader, o.rigid_body_name);
  for (std::size_t i = 800; i < 805; ++i) track.q_TB[i] = track.q_TB[i] * Eigen::Quaterniond(0, 1, 0, 0);
  const TrackingEvalResult r = EvaluateTracking(track, commanded);
  EXPECT_EQ(r.excluded.orientation_flip, 5u);
  EXPECT_LT(r.rotation.max, DegToRad(0.1));
}

TEST(TrackingEvalStandaloneTest, WrongCommandLogIsRejected) {
  const PoseTrajectory commanded = testing::TestMotion(20.0);
  SyntheticTrackerOptions o;
  MotiveReader reader(testing::WriteTake(commanded, o), "take.csv");
  const RigidBodyTrack track = ReadRigidBodyTrack(reader, o.rigid_body_name);
  PoseTrajectory still;
  still.Add(0, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  still.Add(1, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  EXPECT_THROW(EvaluateTracking(track, still), std::runtime_error);
}

TEST(SyntheticTrackerTest, WritesExactlyTheRequestedGapsAndRefusesWhatCannotFit) {
  const PoseTrajectory motion = testing::TestMotion(10.0);
  SyntheticTrackerOptions o;
  const int max_gaps = MaxOcclusionGaps(motion, o);
  // Frames 0 to 11 s at 120 Hz (no negative frame numbers); the middle 90 % in slots of the longest gap (36 frames)
  // plus one visible frame.
  EXPECT_EQ(SyntheticFrameCount(motion, o), 1321);
  EXPECT_EQ(max_gaps, 32);
  for (int gaps : {1, 7, max_gaps}) {
    o.occlusion_gaps = gaps;
    o.seed = static_cast<std::uint32_t>(gaps);
    std::ostringstream out;
    const SyntheticRecording rec = WriteSyntheticMotiveCsv(motion, o, out);
    EXPECT_EQ(rec.gaps, gaps);
    MotiveReader reader(out.str(), "synthetic.csv");
    const MotiveTakeSummary summary = InspectMotiveTake(reader);
    ASSERT_EQ(summary.rigid_bodies.size(), 1u);
    EXPECT_EQ(summary.rigid_bodies[0].gaps.gaps, gaps);
    EXPECT_LE(rec.frames_occluded, 36LL * gaps);
  }
  o.occlusion_gaps = max_gaps + 1;
  std::ostringstream out;
  EXPECT_THROW(WriteSyntheticMotiveCsv(motion, o, out), std::invalid_argument);
  EXPECT_TRUE(out.str().empty());
}

TEST(SyntheticTrackerTest, RefusesNamesThatBreakTheCsv) {
  for (const std::string& name : std::vector<std::string>{
           "a,b", "", "a\"b", "a\nb", "a\tb", " a", "a ", std::string(65, 'r')}) {
    EXPECT_FALSE(MotiveAssetNameProblem(name).empty()) << name;
    SyntheticTrackerOptions o;
    o.rigid_body_name = name;
    std::ostringstream out;
    EXPECT_THROW(WriteSyntheticMotiveCsv(testing::TestMotion(2.0), o, out), std::invalid_argument) << name;
    EXPECT_TRUE(out.str().empty());
  }
  for (const std::string& name : std::vector<std::string>{"MovingRing", "My Ring_1", "ring:2", std::string(64, 'r')}) {
    EXPECT_EQ(MotiveAssetNameProblem(name), "") << name;
  }
}

TEST(StatsTest, MatchesHandComputedValues) {
  const ErrorStats s = ComputeStats({1, 2, 3, 4, 10});
  EXPECT_DOUBLE_EQ(s.mean, 4);
  EXPECT_DOUBLE_EQ(s.median, 3);
  EXPECT_DOUBLE_EQ(s.max, 10);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt((1 + 4 + 9 + 16 + 100) / 5.0));
  EXPECT_DOUBLE_EQ(s.std, std::sqrt((9 + 4 + 1 + 0 + 36) / 5.0));
  EXPECT_DOUBLE_EQ(s.p95, 4 + 0.8 * 6);  // position 3.8 between 4 and 10
}

}  // namespace
}  // namespace robossis::calibration
