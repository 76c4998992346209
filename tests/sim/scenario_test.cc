// Scenarios: accuracy goals, determinism, loads and statics under motion, and parameter errors.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "robot/rsr_kinematics.h"
#include "robot/sim/scenario.h"
#include "sim_fixture.h"

namespace robossis::sim {
namespace {

using ::testing::HasSubstr;
using testing::Data;

ScenarioResult RunKind(ScenarioKind kind, double load_n, double load_nm, double duration_s, double record_hz = 10) {
  ScenarioParams p;
  p.kind = kind;
  p.load_n = load_n;
  p.load_nm = load_nm;
  p.duration_s = duration_s;
  p.record_hz = record_hz;
  return RunScenario(Data().model, Data().config, Data().fragments, p);
}

TEST(ScenarioTest, UnloadedSinusoidMeetsTheAccuracyGoal) {
  // Goal: <= 0.02 mm and <= 0.01 deg unloaded (the paper's Gazebo model: ~0.2 mm, ~0.1 deg, §IV).
  const ScenarioSummary s = RunKind(ScenarioKind::kSinusoid, 0, 0, 6).summary;
  EXPECT_LE(s.max_translation_error_mm, 0.02);
  EXPECT_LE(s.max_rotation_error_deg, 0.01);
  EXPECT_FALSE(s.actuator_limit_reached);
  EXPECT_FALSE(s.unstable);
}

TEST(ScenarioTest, LoadedSinusoidForcesMatchJacobianStaticsWithin5Percent) {
  const ScenarioSummary s = RunKind(ScenarioKind::kSinusoid, 517, 74, 6).summary;
  EXPECT_LE(s.max_translation_error_mm, 0.02);
  EXPECT_LE(s.max_rotation_error_deg, 0.01);
  EXPECT_GT(s.statics_steps, 5000);
  EXPECT_LE(s.statics_linear_rel_error, 0.05);
  EXPECT_LE(s.statics_rotary_rel_error, 0.05);
  EXPECT_GT(s.max_actuator_force_n, 150);  // the traction is carried (517 N / 3 at the reference)
  EXPECT_FALSE(s.actuator_limit_reached);
}

TEST(ScenarioTest, ReductionReachesAlignmentAgainstTheFullTraction) {
  const ScenarioResult r = RunKind(ScenarioKind::kReduction, 517, 74, 8);
  const ScenarioSummary& s = r.summary;
  EXPECT_LE(s.max_translation_error_mm, 0.02);
  EXPECT_LE(s.max_rotation_error_deg, 0.01);
  EXPECT_NEAR(s.peak_traction_torque_nm, 74, 1.0);  // derotated fully: the torsion reaches its calibrated 74 N·m
  EXPECT_GE(s.peak_traction_n, 517 - 1.0);
  EXPECT_LE(s.max_penetration_mm, s.penetration_tolerance_mm);
  EXPECT_LE(s.statics_linear_rel_error, 0.05);
  // Ends aligned: the final gap of sim.yaml along the axis, no rotation.
  const ScenarioSample& last = r.samples.back();
  EXPECT_NEAR(last.pose_meas_mm_deg[2], 284 + Data().config.reduction.final_gap_m * 1e3, 1e-3);
  for (int k : {0, 1, 3, 4, 5}) EXPECT_NEAR(last.pose_meas_mm_deg[k], 0, 1e-3) << k;
}

TEST(ScenarioTest, SameRunTwiceGivesTheSameResult) {
  const ScenarioResult a = RunKind(ScenarioKind::kReduction, 517, 74, 1.5, 100);
  const ScenarioResult b = RunKind(ScenarioKind::kReduction, 517, 74, 1.5, 100);
  // Timing columns aside, bit for bit.
  EXPECT_EQ(TrajectoryCsv(a), TrajectoryCsv(b));
  EXPECT_EQ(a.summary.max_actuator_force_n, b.summary.max_actuator_force_n);
}

TEST(ScenarioTest, ArmGravityWrenchMatchesVirtualWorkOfALiftedRing) {
  // Reference (closed form): at home the legs are vertical, so with gravity along -z lifting the ring by dz lifts
  // each rod by dz and no actuator body (it only turns about A_i): W_z = -dV/dz = -3 m_rod g; no x force, no z moment.
  const MassConfig& m = Data().config.masses;
  const Eigen::Vector3d g(0, 0, -9.81);
  const Eigen::Isometry3d X = Data().model.geometry().X_FM_home;
  const Vector6d W = ArmGravityWrench(Data().model, m, g, X);
  EXPECT_NEAR(W[2], -3 * m.piston_kg * 9.81, 1e-5);
  EXPECT_NEAR(W[0], 0, 1e-6);
  EXPECT_NEAR(W[5], 0, 1e-6);
}

TEST(ScenarioTest, BadParametersGiveClearErrors) {
  ScenarioParams p;
  p.load_n = -5;
  EXPECT_THAT([&] { ValidateScenarioParams(p, Data().config); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("--load-n")));
  p = ScenarioParams{};
  p.load_nm = std::nan("");
  EXPECT_THAT([&] { ValidateScenarioParams(p, Data().config); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("--load-nm")));
  p = ScenarioParams{};
  p.duration_s = 0;
  EXPECT_THAT([&] { ValidateScenarioParams(p, Data().config); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("--duration-s")));
  EXPECT_THAT([] { ParseScenarioKind("circle"); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("'sinusoid' or 'reduction'")));
}

TEST(ScenarioTest, TrajectoryLeavingTheWorkspaceIsRejectedWithItsTime) {
  SimConfig config = Data().config;
  config.sinusoid.amplitude_m.x() = 0.2;  // far beyond the ~130 mm reach
  ScenarioParams p;
  p.duration_s = 20;
  EXPECT_THAT([&] { RunScenario(Data().model, config, Data().fragments, p); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("commanded pose at t =")));
}

}  // namespace
}  // namespace robossis::sim
