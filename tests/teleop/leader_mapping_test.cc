// The leader's one hand-to-robot mapping with a rotated R_FO (transfer.yaml `mapping`): the hand moving along d in O
// sends the set-points, and the walls' pose, along R_FO·d·scale in F; a wall the ring presses into pushes the hand
// back against its motion in O. The directions compared are far apart when the rotation is dropped on either side
// (guards assert it), so each check fails without it; the identity frame moves the robot along the hand's own d.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "haptics/device/simulated_device.h"
#include "haptics/scenarios/scenario.h"
#include "robot/rsr_kinematics.h"
#include "src/core/pose.h"
#include "src/core/rt/periodic_loop.h"
#include "src/core/units.h"
#include "src/teleop/leader_unit.h"
#include "tests/teleop/teleop_fixture.h"

namespace robossis::teleop {
namespace {

using namespace testing;

struct Rotation {
  std::string name;
  Eigen::Matrix3d R_FO;
};

std::vector<Rotation> Rotations() {
  return {{"identity", Eigen::Matrix3d::Identity()},
          {"yaw 90 deg", RotationFromRpy(Eigen::Vector3d(0, 0, DegToRad(90)))},
          {"roll 25, pitch -40, yaw 110 deg", RotationFromRpy(Eigen::Vector3d(DegToRad(25), DegToRad(-40),
                                                                              DegToRad(110)))}};
}

double Cosine(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return a.dot(b) / (a.norm() * b.norm()); }

// A hand at rest at the device centre for 0.3 s, then along d_O at `speed` for `travel`, then held there.
haptics::HandScript StraightHand(const Eigen::Vector3d& d_O, double travel_m, double speed_m_s) {
  haptics::HandScript s;
  s.name = "straight";
  const Eigen::Vector3d c = Sigma7().p_center_O();
  const double start = 0.3, end = start + travel_m / speed_m_s;
  s.target = [c, d_O, travel_m, speed_m_s, start, end](double t) {
    haptics::HandTarget h;
    const double along = t < start ? 0 : t > end ? travel_m : (t - start) * speed_m_s;
    h.X_OH.translation() = c + along * d_O;
    if (t >= start && t <= end) h.v_O = speed_m_s * d_O;
    return h;
  };
  return s;
}

struct LeaderRun {
  Eigen::Vector3d setpoint_moved_F;  // the last set-point minus home
  Eigen::Vector3d goal_moved_F;      // the last pose the walls were rendered at (the transfer's) minus home
  Eigen::Vector3d f_O;               // the last force sent to the device
  Eigen::Vector3d hand_moved_O;      // the hand's displacement
  bool all_feasible = true;
};

LeaderRun RunLeader(const transfer::HcToRsrFrame& frame, const haptics::HandScript& script, double seconds) {
  LeaderConfig config = Leader();
  transfer::TransferConfig transfer = Transfer();
  static_cast<transfer::HcToRsrFrame&>(transfer.mapping) = frame;
  // Caps far above the paper's, so that the set-point keeps up with the hand (eq. 11 scales nothing).
  transfer.caps.max_linear_speed_m_s = 0.25;
  transfer.caps.max_angular_speed_rad_s = DegToRad(60);
  haptics::SimulatedDevice device(Sigma7(), Haptics().device, Haptics().hand, script, config.device);
  device.EnableForces(true);
  // Built with the default (identity) frame, as the sessions build it: the leader gives it the transfer's.
  std::unique_ptr<haptics::HapticRenderer> renderer = Renderer("proxy-safe", config.rate_hz);
  RecordingLeaderLink link(static_cast<std::size_t>(seconds * 1000) + 10);
  const Eigen::Isometry3d home = Rsr().geometry().X_FM_home;
  LeaderUnit unit(config, transfer, Rsr(), device, *renderer, link, home, 7);
  rt::SimulatedClock clock;
  LeaderTickRecord first, last;
  bool have_first = false;
  rt::LoopOptions o;
  o.period_ns = static_cast<std::int64_t>(1e9 / config.rate_hz);
  rt::RunSimulated(clock, {{&unit, o}}, seconds, [&](double) {
    LeaderTickRecord r;
    while (unit.records().TryPop(r)) {
      if (!have_first) first = r;
      have_first = true;
      last = r;
    }
    return true;
  });
  LeaderRun run;
  for (const SetPointMessage& m : link.sent) {
    run.all_feasible = run.all_feasible && robot::IsPoseFeasible(Rsr(), PoseFromArrays(m.p_FM, m.q_FM));
  }
  run.setpoint_moved_F = PoseFromArrays(link.last.p_FM, link.last.q_FM).translation() - home.translation();
  run.goal_moved_F = Eigen::Vector3d(last.p_goal[0], last.p_goal[1], last.p_goal[2]) - home.translation();
  run.f_O = Eigen::Vector3d(last.f_O[0], last.f_O[1], last.f_O[2]);
  run.hand_moved_O = Eigen::Vector3d(last.p_OH[0] - first.p_OH[0], last.p_OH[1] - first.p_OH[1],
                                     last.p_OH[2] - first.p_OH[2]);
  return run;
}

// (a) and (c): 15 mm of hand along d in O moves the set-point and the walls' pose along R_FO·d·scale in F.
TEST(LeaderMappingTest, TheHandAlongDMovesTheSetPointAndTheWallsAlongRfoD) {
  const Eigen::Vector3d d_O = Eigen::Vector3d(0.8, -0.3, 0.2).normalized();
  const double scale = 1.5, travel = 0.015;
  for (const Rotation& rotation : Rotations()) {
    SCOPED_TRACE(rotation.name);
    transfer::HcToRsrFrame frame;
    frame.R_FO = rotation.R_FO;
    frame.translation_scale = scale;
    const Eigen::Vector3d expected_F = scale * travel * (rotation.R_FO * d_O);
    if (rotation.name != "identity") {
      ASSERT_LT(Cosine(expected_F, d_O), 0.5);  // an ignored R_FO would fail
    }
    const LeaderRun run = RunLeader(frame, StraightHand(d_O, travel, 0.03), 1.8);
    EXPECT_TRUE(run.all_feasible);
    // The simulated hand lags its target a little: compare with where the hand went.
    EXPECT_GT(Cosine(run.hand_moved_O, d_O), 0.999);
    const Eigen::Vector3d hand_expected_F = frame.LinearToRsr(run.hand_moved_O);
    EXPECT_LT((run.hand_moved_O.norm() - travel) / travel, 0.05);
    EXPECT_GT(Cosine(run.setpoint_moved_F, expected_F), 0.995) << run.setpoint_moved_F.transpose();
    EXPECT_LT((run.setpoint_moved_F - hand_expected_F).norm(), 0.05 * hand_expected_F.norm());
    EXPECT_GT(Cosine(run.goal_moved_F, expected_F), 0.995) << run.goal_moved_F.transpose();
    EXPECT_LT((run.goal_moved_F - hand_expected_F).norm(), 0.05 * hand_expected_F.norm());
    // Free space: no wall force.
    EXPECT_LT(run.f_O.norm(), 1.0);
  }
}

// (b): the hand moves along d in O, so the ring goes along R_FO·d in F, past its wall; the force on the hand, in O,
// opposes the hand's motion. The wall's own force (about −R_FO·d in F), sent unrotated, would be nearly
// perpendicular to d (the guard below).
TEST(LeaderMappingTest, AWallTheRingPressesIntoPushesTheHandBackInO) {
  const Eigen::Vector3d d_O = Eigen::Vector3d(0.8, -0.3, 0.2).normalized();  // where the sigma.7 has room
  const Eigen::Isometry3d home = Rsr().geometry().X_FM_home;
  const double hand_to_wall = 0.035;  // m of hand travel to the wall
  for (const Rotation& rotation : Rotations()) {
    SCOPED_TRACE(rotation.name);
    const Eigen::Vector3d axis_F = rotation.R_FO * d_O;
    const double reach = haptics::ReachAlongAxis(Rsr(), home, axis_F, false, 0.3);
    ASSERT_GT(reach, 0.05);
    transfer::HcToRsrFrame frame;
    frame.R_FO = rotation.R_FO;
    frame.translation_scale = reach / hand_to_wall;
    if (rotation.name != "identity") {
      ASSERT_GT(Cosine(-axis_F, d_O), -0.1);  // unrotated: not against d
    }
    const LeaderRun run = RunLeader(frame, StraightHand(d_O, hand_to_wall + 0.015, 0.03), 2.5);
    EXPECT_TRUE(run.all_feasible);
    // The ring was sent along R_FO·d to the wall, and the transfer's goal (where the walls are rendered) with it (the
    // wall pushes the hand back a little, and the goal with the hand).
    EXPECT_GT(Cosine(run.setpoint_moved_F, axis_F), 0.95) << run.setpoint_moved_F.transpose();
    EXPECT_GT(run.setpoint_moved_F.dot(axis_F), reach - 0.01);
    EXPECT_GT(Cosine(run.goal_moved_F, axis_F), 0.95) << run.goal_moved_F.transpose();
    EXPECT_GT(run.goal_moved_F.dot(axis_F), reach - 0.01);
    ASSERT_GT(run.f_O.norm(), 2.0);
    // Measured: −0.96 (identity, yaw 90°) and −0.82 (general); the unrotated force gives −0.11 and −0.18.
    EXPECT_LT(Cosine(run.f_O, d_O), -0.7) << "f_O " << run.f_O.transpose() << ", d_O " << d_O.transpose();
  }
}

}  // namespace
}  // namespace robossis::teleop
