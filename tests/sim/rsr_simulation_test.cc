// The Bullet model of the RSR: kinematics, statics against J^-T, contact, drive limits, the follower interface.

#include <algorithm>

#include <gtest/gtest.h>

#include "robot/rsr_kinematics.h"
#include "robot/sim/rsr_simulation.h"
#include "sim_fixture.h"
#include "src/core/units.h"
#include "tests/support/alloc_counter.h"

namespace robossis::sim {
namespace {

using testing::Data;

Eigen::Isometry3d Home() { return Data().model.geometry().X_FM_home; }

// A pose off home (translated and tilted), where the statics are not symmetric.
Eigen::Isometry3d OffHome() {
  Vector6d p;
  p << 15, -10, 300, 4, -3, 8;  // mm, deg
  return PoseFromMmDeg(p);
}

MuscleTraction Traction(const Eigen::Isometry3d& X_ref, double load_n, double load_nm) {
  MuscleTraction t(Data().config.traction, Eigen::Vector3d::UnitZ(), Data().fragments.fracture_site_F, Home());
  t.Calibrate(X_ref, X_ref.linear(), load_n, load_nm);
  return t;
}

void Hold(RsrSimulation& sim, const Eigen::Isometry3d& X, double seconds) {
  robot::RsrJointCommand cmd;
  cmd.q = robot::CalcInverseKinematics(Data().model, X).joints.actuated();
  const long n = std::lround(seconds / sim.step_s());
  for (long k = 0; k < n; ++k) {
    cmd.time_s = sim.time_s() + sim.step_s();
    sim.Command(cmd);
    sim.Step();
  }
}

TEST(RsrSimulationTest, StartsOnTheCommandedPoseWithTheIkJoints) {
  RsrSimulation sim(Data().model, Data().config, &Data().fragments, nullptr, OffHome());
  const robot::RsrFollowerState s = sim.State();
  EXPECT_LT((s.X_FM.translation() - OffHome().translation()).norm(), 1e-12);
  EXPECT_LT(RotationAngleBetween(s.X_FM.linear(), OffHome().linear()), 1e-12);
  const robot::RsrJointVector q_ik = robot::CalcInverseKinematics(Data().model, OffHome()).joints.actuated();
  EXPECT_LT((s.q - q_ik).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(RsrSimulationTest, StaticEquilibriumMatchesJacobianStatics) {
  // No gravity: the only load on the ring is the muscle traction (517 N, 74 N·m, paper §I). The drives must then
  // exert Q = -J^-T W (eq. 15 statics, robot::CalcActuatorEfforts) — the issue asks for 5%; the model gives far less.
  SimOptions options;
  options.gravity = false;
  const MuscleTraction traction = Traction(OffHome(), 517, 74);
  RsrSimulation sim(Data().model, Data().config, &Data().fragments, &traction, OffHome(), options);
  Hold(sim, OffHome(), 0.5);
  const robot::RsrFollowerState s = sim.State();
  // The external wrench the simulation reports with the measurement is the one the drives hold.
  ASSERT_TRUE(s.true_wrench_known);
  const robot::RsrStaticsResult expected = robot::CalcActuatorEfforts(Data().model, s.X_FM, s.true_wrench_F);
  ASSERT_FALSE(expected.singular);
  EXPECT_NEAR(sim.diagnostics().traction.axial_force_n, 517, 1.0);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(s.effort[robot::StrokeIndex(i)], expected.linear_force_n[i],
                0.01 * expected.linear_force_n.cwiseAbs().maxCoeff()) << "linear drive " << i + 1;
    EXPECT_NEAR(s.effort[robot::ThetaIndex(i)], expected.rotary_torque_nm[i],
                0.01 * expected.rotary_torque_nm.cwiseAbs().maxCoeff()) << "rotary drive " << i + 1;
  }
}

// Each measurement carries the muscles' wrench of the step that made it, evaluated at the pose and the measured
// velocity that step started from, [force at P; moment about P] in F (the wrench estimate's convention), while the
// ring moves (the dampers count); none before the first step.
TEST(RsrSimulationTest, ReportsTheMusclesWrenchOfEachStepWithItsMeasurement) {
  const MuscleTraction traction = Traction(OffHome(), 517, 74);
  SimOptions options;
  options.with_bone = false;
  RsrSimulation sim(Data().model, Data().config, nullptr, &traction, OffHome(), options);
  ASSERT_TRUE(sim.State().true_wrench_known);
  EXPECT_EQ(sim.State().true_wrench_F, Vector6d::Zero());
  Vector6d moved;
  moved << 15, -10, 310, 4, -3, 11;  // mm, deg: 10 mm along the femur axis, 3 deg about it
  const robot::RsrJointVector q0 = robot::CalcInverseKinematics(Data().model, OffHome()).joints.actuated();
  const robot::RsrJointVector q1 = robot::CalcInverseKinematics(Data().model, PoseFromMmDeg(moved)).joints.actuated();
  constexpr double kRampS = 0.5;
  double max_damping_n = 0;  // the muscles' wrench at the measured velocity against the one at rest, same pose
  robot::RsrJointCommand cmd;
  for (long k = 1; k <= 700; ++k) {
    const double t = k * sim.step_s();
    const double a = std::min(1.0, t / kRampS);
    cmd.time_s = t;
    cmd.q = q0 + a * (q1 - q0);
    cmd.q_dot = t < kRampS ? robot::RsrJointVector((q1 - q0) / kRampS) : robot::RsrJointVector::Zero();
    sim.Command(cmd);
    const Eigen::Isometry3d X_start = sim.State().X_FM;
    const Eigen::Vector3d v_start = sim.diagnostics().v_P_F;
    const Eigen::Vector3d w_start = sim.diagnostics().w_F;
    ASSERT_EQ(sim.Step(), SimStepStatus::kOk) << "at t = " << sim.time_s();
    const robot::RsrFollowerState s = sim.State();
    const Vector6d applied = traction.Evaluate(X_start, v_start, w_start).wrench_P_F;
    ASSERT_TRUE(s.true_wrench_known);
    ASSERT_LE((s.true_wrench_F - applied).norm(), 1e-9 * applied.norm()) << "at t = " << s.time_s;
    const Vector6d at_rest = traction.Evaluate(X_start, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()).wrench_P_F;
    max_damping_n = std::max(max_damping_n, (applied - at_rest).head<3>().norm());
  }
  EXPECT_GT(max_damping_n, 3.0);  // 300 N·s/m at 20 mm/s: the velocity mattered
}

// Home distracted by 5 mm along the axis: the legs stay parallel to it and the cut faces 5 mm apart (at home
// itself they touch).
Eigen::Isometry3d Distracted() {
  Eigen::Isometry3d X = Home();
  X.translation().z() += 0.005;
  return X;
}

TEST(RsrSimulationTest, AxialTractionSplitsEquallyOverTheLinearDrives) {
  // The assumed geometry (README.md): at home a 517 N axial load gives ~172 N per linear actuator (517/3 = 172.3 N).
  SimOptions options;
  options.gravity = false;
  const MuscleTraction traction = Traction(Distracted(), 517, 0);
  RsrSimulation sim(Data().model, Data().config, &Data().fragments, &traction, Distracted(), options);
  Hold(sim, Distracted(), 0.2);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(sim.State().effort[robot::StrokeIndex(i)], 517.0 / 3.0, 0.5);
    EXPECT_NEAR(sim.State().effort[robot::ThetaIndex(i)], 0.0, 0.05);
  }
}

TEST(RsrSimulationTest, HoldsALoadedPoseFor60SecondsWithoutDrift) {
  // 60 s of simulated time at 1 kHz, with gravity and the full traction: the ring must stay on the commanded pose.
  const MuscleTraction traction = Traction(OffHome(), 517, 74);
  RsrSimulation sim(Data().model, Data().config, &Data().fragments, &traction, OffHome());
  robot::RsrJointCommand cmd;
  cmd.q = robot::CalcInverseKinematics(Data().model, OffHome()).joints.actuated();
  double worst_t = 0, worst_r = 0, worst_loop = 0;
  for (long k = 0; k < 60000; ++k) {
    cmd.time_s = sim.time_s() + sim.step_s();
    sim.Command(cmd);
    ASSERT_NE(sim.Step(), SimStepStatus::kUnstable) << "at t = " << sim.time_s();
    const robot::RsrFollowerState s = sim.State();
    worst_t = std::max(worst_t, (s.X_FM.translation() - OffHome().translation()).norm());
    worst_r = std::max(worst_r, RotationAngleBetween(s.X_FM.linear(), OffHome().linear()));
    worst_loop = std::max(worst_loop, sim.diagnostics().max_loop_error_m);
  }
  EXPECT_NEAR(sim.time_s(), 60.0, 1e-9);
  EXPECT_LT(worst_t, MmToM(0.02));    // the simulation's accuracy goal
  EXPECT_LT(worst_r, DegToRad(0.01));
  EXPECT_LT(worst_loop, 1e-7);
  EXPECT_LT(sim.diagnostics().v_P_F.norm(), 1e-6);  // at rest: no energy creeping in
}

TEST(RsrSimulationTest, PressedFragmentsDoNotInterpenetrateBeyondTheTolerance) {
  // Bring the distal fragment down onto the proximal one and command it 3 mm further: the contact must hold (the
  // drives give way at their limit) and the fragments overlap by no more than bone.penetration_tolerance_m.
  Eigen::Isometry3d start = Home();
  start.translation().z() += 0.002;
  Eigen::Isometry3d pressed = Home();
  pressed.translation().z() -= 0.003;
  RsrSimulation sim(Data().model, Data().config, &Data().fragments, nullptr, start);
  robot::RsrJointCommand cmd;
  const robot::RsrJointVector q0 = robot::CalcInverseKinematics(Data().model, start).joints.actuated();
  const robot::RsrJointVector q1 = robot::CalcInverseKinematics(Data().model, pressed).joints.actuated();
  double max_pen = 0;
  int contact_steps = 0;
  bool limit_seen = false;
  for (long k = 1; k <= 1500; ++k) {
    const double s = std::min(1.0, k / 1000.0);  // 5 mm in 1 s, then hold for 0.5 s
    cmd.time_s = k * sim.step_s();
    cmd.q = q0 + s * (q1 - q0);
    sim.Command(cmd);
    const SimStepStatus status = sim.Step();
    ASSERT_NE(status, SimStepStatus::kUnstable) << "at t = " << sim.time_s();
    limit_seen = limit_seen || status == SimStepStatus::kActuatorLimit;
    max_pen = std::max(max_pen, sim.diagnostics().max_penetration_m);
    if (sim.diagnostics().contact_points > 0) ++contact_steps;
    // The contact's load is the solver's, not set by the simulation: the true external wrench is then not known.
    if (sim.diagnostics().contact_points > 0) {
      ASSERT_FALSE(sim.State().true_wrench_known) << "at t = " << sim.time_s();
    }
    if (k == 1) {
      EXPECT_TRUE(sim.State().true_wrench_known);  // 2 mm apart: nothing but the (absent) muscles
    }
  }
  EXPECT_GT(contact_steps, 100);
  EXPECT_TRUE(limit_seen);  // the drives cannot push through bone: the simulation says so
  EXPECT_LE(max_pen, Data().config.bone.penetration_tolerance_m);
  RecordProperty("max_penetration_um", std::to_string(max_pen * 1e6));
  // The ring stopped at the contact, short of the commanded pose.
  EXPECT_GT(sim.State().X_FM.translation().z(), pressed.translation().z() + 0.002);
}

TEST(RsrSimulationTest, ReportsTheActuatorLimitWhenTheLoadExceedsTheDrives) {
  // 4000 N of traction at home needs 1333 N per linear drive, above the 1100 N the paper gives.
  const MuscleTraction traction = Traction(Distracted(), 4000, 0);
  RsrSimulation sim(Data().model, Data().config, &Data().fragments, &traction, Distracted());
  robot::RsrJointCommand cmd;
  cmd.q = robot::CalcInverseKinematics(Data().model, Distracted()).joints.actuated();
  bool limit_seen = false;
  for (int k = 0; k < 50; ++k) {
    cmd.time_s = sim.time_s() + sim.step_s();
    sim.Command(cmd);
    limit_seen = limit_seen || sim.Step() == SimStepStatus::kActuatorLimit;
  }
  EXPECT_TRUE(limit_seen);
  EXPECT_EQ(sim.State().fault, robot::FollowerFault::kDrive);
  EXPECT_TRUE(sim.diagnostics().linear_saturated[0] && sim.diagnostics().linear_saturated[1]);
  EXPECT_NEAR(std::abs(sim.State().effort[robot::StrokeIndex(0)]), Data().config.actuators.linear_force_max_n, 1e-6);
}

TEST(RsrSimulationTest, VelocityModeFollowsTheJointVelocities) {
  SimConfig config = Data().config;
  config.actuators.mode = DriveMode::kVelocity;
  RsrSimulation sim(Data().model, config, nullptr, nullptr, Home(), SimOptions{false, false, false});
  robot::RsrJointCommand cmd;
  cmd.q = robot::CalcInverseKinematics(Data().model, Home()).joints.actuated();
  cmd.q_dot << 0, 0, 0, 0.01, 0.01, 0.01;  // all legs out at 10 mm/s: the ring rises along z
  for (int k = 0; k < 500; ++k) {
    cmd.time_s = sim.time_s();
    sim.Command(cmd);
    sim.Step();
  }
  EXPECT_NEAR(sim.State().X_FM.translation().z() - Home().translation().z(), 0.005, 1e-6);
}

TEST(RsrSimulationTest, FollowerCallsDoNotAllocate) {
  RsrSimulation sim(Data().model, Data().config, &Data().fragments, nullptr, Distracted());
  robot::Follower& follower = sim;
  robot::RsrJointCommand cmd;
  cmd.q = robot::CalcInverseKinematics(Data().model, Distracted()).joints.actuated();
  sim.Step();
  robossis::testing::AllocationCounter counter;
  for (int k = 0; k < 100; ++k) {
    follower.Command(cmd);
    const robot::RsrFollowerState s = follower.State();
    ASSERT_FALSE(s.faulted());
  }
  EXPECT_EQ(counter.count(), 0u);
}

TEST(RsrSimulationTest, StepAllocatesNothingOnceWarmedUp) {
  // Bullet sizes its buffers in the first steps; after that a loaded hold (traction, no new contact pairs) runs
  // without touching the heap. New contact pairs may still allocate (Bullet's manifold pool).
  const MuscleTraction traction = Traction(Distracted(), 517, 74);
  RsrSimulation sim(Data().model, Data().config, &Data().fragments, &traction, Distracted());
  robot::RsrJointCommand cmd;
  cmd.q = robot::CalcInverseKinematics(Data().model, Distracted()).joints.actuated();
  auto step = [&] {
    cmd.time_s = sim.time_s() + sim.step_s();
    sim.Command(cmd);
    return sim.Step();
  };
  for (int k = 0; k < 20; ++k) step();
  robossis::testing::AllocationCounter counter;
  for (int k = 0; k < 200; ++k) ASSERT_EQ(step(), SimStepStatus::kOk);
  EXPECT_EQ(counter.count(), 0u);
}

TEST(RsrSimulationTest, InfeasibleStartPoseIsRejected) {
  Eigen::Isometry3d X = Home();
  X.translation().z() += 0.2;  // legs beyond 354 mm
  EXPECT_THROW(RsrSimulation(Data().model, Data().config, nullptr, nullptr, X), std::invalid_argument);
}

}  // namespace
}  // namespace robossis::sim
