// The panel's simulated follower, driven in simulated time (Step() without the loop thread, 10 kHz follower ticks):
// the follower unit's states as the panel sees them, a jog played as set-points moving the Bullet RSR by the
// requested amount, refusals leaving it still, the E-stop latching, and a tick that allocates nothing; haptic mode
// with the runtime's leader unit and the simulated sigma.7 (the hand pushing into a wall is felt), its clutch, and
// its settings changing only while clutched.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <unistd.h>

#include "haptics/rendering/renderer_factory.h"

#include "src/core/rt/clock.h"
#include "src/core/config.h"
#include "src/core/units.h"
#include "src/panel/local_session_backend.h"
#include "src/panel/panel_controller.h"
#include "src/panel/script.h"
#include "src/panel/view_model.h"
#include "src/teleop/teleop_session.h"
#include "tests/support/alloc_counter.h"

namespace robossis::panel {
namespace {

using teleop::OperatingState;
using teleop::StateCommand;

class LocalSessionBackendTest : public ::testing::Test {
 protected:
  static JogLimits Limits(const teleop::FollowerConfig& follower) {
    JogLimits limits;
    limits.setpoint = follower.setpoint;  // the preview's limits are the follower unit's
    return limits;
  }

  LocalSessionBackendTest()
      : model_(robot::RsrModel::FromYaml(DefaultDataDir() / "config" / "rsr.yaml")),
        sigma7_(robot::Sigma7Model::FromYaml(DefaultDataDir() / "config" / "sigma7.yaml")),
        setup_(teleop::TeleopSetup::Load(DefaultDataDir(), model_, sigma7_)),
        backend_(model_, teleop::MakeFollowerBackEnd("sim", setup_, 0), setup_.follower, setup_.actuation,
                 Limits(setup_.follower), setup_.transfer.rates, clock_) {}

  void Run(double seconds) {
    const int ticks = static_cast<int>(seconds * 10000 + 0.5);
    for (int i = 0; i < ticks; ++i) {
      clock_.AdvanceNs(100'000);  // 10 kHz
      backend_.Step();
    }
  }
  teleop::FollowerStatusMessage Status() {
    teleop::FollowerStatusMessage status;
    EXPECT_TRUE(backend_.ReadStatus(status));
    return status;
  }
  void HomeToReady() {
    ASSERT_TRUE(backend_.SendCommand(StateCommand::kHome));
    ASSERT_TRUE(backend_.SendCommand(StateCommand::kEnable));
    Run(0.2);
    ASSERT_EQ(Status().state, OperatingState::kReady);
  }
  JogRequest JogZ(double mm, double duration_s) {
    JogRequest request;
    request.axis = JogAxis::kZ;
    request.amount = MmToM(mm);
    request.duration_s = duration_s;
    return request;
  }

  // The panel's haptic leader as `robossis panel` attaches it, with the given device.
  void AttachLeader(const std::string& device) {
    backend_.AttachHapticLeader({&sigma7_, setup_.haptics, setup_.transfer, setup_.leader, device, nullptr});
  }
  static HapticModeRequest Haptic(bool enabled, bool clutched, const std::string& method, double linear_mm_s) {
    const std::vector<std::string> methods = haptics::KnownMethods();
    HapticModeRequest request;
    request.enabled = enabled;
    request.clutched = clutched;
    request.rendering_method =
        static_cast<int>(std::find(methods.begin(), methods.end(), method) - methods.begin());
    request.max_linear_speed_m_s = MmToM(linear_mm_s);
    request.max_angular_speed_rad_s = DegToRad(1);
    return request;
  }
  double HandForceN() {
    HandWrench wrench;
    EXPECT_TRUE(backend_.ReadHandWrench(wrench));
    return std::hypot(wrench.force_n[0], wrench.force_n[1], wrench.force_n[2]);
  }

  rt::SimulatedClock clock_;
  robot::RsrModel model_;
  robot::Sigma7Model sigma7_;
  teleop::TeleopSetup setup_;
  LocalSessionBackend backend_;
};

TEST_F(LocalSessionBackendTest, StartsDisabledAndRefusesJogsUntilHomed) {
  Run(0.05);
  EXPECT_EQ(Status().state, OperatingState::kDisabled);
  const JogVerdict verdict = backend_.StartJog(JogZ(5, 2));
  EXPECT_FALSE(verdict.accepted);
  EXPECT_NE(verdict.reason.find("disabled"), std::string::npos) << verdict.reason;
  HomeToReady();
}

TEST_F(LocalSessionBackendTest, AJogMovesTheRobotByTheRequestedAmount) {
  HomeToReady();
  const Eigen::Vector3d start = PoseOf(Status()).translation();
  const JogVerdict verdict = backend_.StartJog(JogZ(5, 1));
  ASSERT_TRUE(verdict.accepted) << verdict.reason;
  Run(2.0);
  const Eigen::Vector3d moved = PoseOf(Status()).translation() - start;
  EXPECT_NEAR(MToMm(moved.z()), 5, 0.05);
  EXPECT_NEAR(MToMm(moved.head<2>().norm()), 0, 0.05);
  LoopHealth health;
  ASSERT_TRUE(backend_.ReadHealth(health));
  EXPECT_GE(health.setpoint_age_s, 0);
}

TEST_F(LocalSessionBackendTest, AJogIsPlayedAsSetPointsThatTheFollowerUnitValidatesAndFollows) {
  HomeToReady();
  const std::uint64_t accepted_before = backend_.follower_counters().setpoints_accepted;
  ASSERT_TRUE(backend_.StartJog(JogZ(5, 1)).accepted);
  Run(0.5);
  EXPECT_EQ(Status().state, OperatingState::kEnabled);  // presence + valid set-points: the unit follows
  Run(1.0);
  EXPECT_EQ(Status().state, OperatingState::kReady);  // the move ended: no presence, the unit holds
  const teleop::FollowerCounters& counters = backend_.follower_counters();
  EXPECT_GE(counters.setpoints_accepted - accepted_before, 1400u);  // 1.5 s of 1 kHz set-points
  EXPECT_EQ(counters.setpoints_rejected, 0u);
  EXPECT_EQ(counters.commands_refused, 0u);
  EXPECT_GT(Status().setpoints_accepted, accepted_before);  // the status the panel shows is the unit's
  LoopHealth health;
  ASSERT_TRUE(backend_.ReadHealth(health));
  EXPECT_EQ(health.setpoints_by_verdict, counters.setpoints_by_verdict);  // and so are the verdicts it shows
}

// A script's waits on the panel's view, in simulated time: the state the follower reached, and a jog done only once
// the player sent its last set-point and the robot got there (what a scripted window run waits for instead of a time).
TEST_F(LocalSessionBackendTest, ScriptWaitsHoldUntilTheStateAndTheJogsEnd) {
  PanelController controller(backend_, model_, PanelConfig{},
                             HapticModeModel(haptics::KnownMethods(), SpeedCapValues{MmToM(10), DegToRad(1)}));
  const auto wait = [](const std::string& line) { return ParseScript(line, "s").at(0); };
  const ScriptAction ready = wait("0 wait state ready\n"), done = wait("0 wait jog.done\n");
  Run(0.01);
  controller.Update(0);
  EXPECT_FALSE(controller.ScriptConditionHolds(ready));
  EXPECT_TRUE(controller.ScriptConditionHolds(wait("0 wait state disabled\n")));
  EXPECT_FALSE(controller.ScriptConditionHolds(done));  // no jog yet
  controller.Click("home");
  controller.Click("enable");
  Run(0.2);
  controller.Update(0);
  EXPECT_TRUE(controller.ScriptConditionHolds(ready));
  controller.Set("jog.axis", "z");
  controller.Set("jog.amount", "2");
  controller.Set("jog.duration_s", "1");
  controller.Click("jog.preview");  // a preview is no jog
  EXPECT_FALSE(controller.ScriptConditionHolds(done));
  controller.Click("jog.go");
  ASSERT_TRUE(controller.last_verdict()->accepted) << controller.last_verdict()->reason;
  const double end_z = controller.last_verdict()->X_FM_end.translation().z();
  int ticks_to_done = 0;
  for (; ticks_to_done < 30000 && !controller.ScriptConditionHolds(done); ticks_to_done += 10) {
    Run(0.001);
    controller.Update(0);
    if (!controller.ScriptConditionHolds(done)) continue;
    Run(0.001);  // done is done: the robot stays where it is
    controller.Update(0);
    EXPECT_TRUE(controller.ScriptConditionHolds(done));
    EXPECT_NEAR(controller.view().X_FM.translation().z(), end_z, PanelController::kJogDonePositionM);
    EXPECT_NEAR((controller.commanded_pose().translation() - controller.last_verdict()->X_FM_end.translation()).norm(),
                0, 1e-6);
  }
  EXPECT_TRUE(controller.ScriptConditionHolds(done)) << "z " << MToMm(controller.view().X_FM.translation().z())
                                                     << " mm, the jog's end " << MToMm(end_z) << " mm";
  // Not before the 1 s jog's end: eq. 9 comes within 1 um of its end in its last 2 % (10 s^3 of 2 mm for s < 0.02).
  EXPECT_GE(ticks_to_done, 9800);
  ScriptAction unknown = done;
  unknown.target = "jog.gone";
  EXPECT_THROW(controller.ScriptConditionHolds(unknown), std::invalid_argument);
}

TEST_F(LocalSessionBackendTest, ARefusedMoveLeavesTheRobotStill) {
  HomeToReady();
  Run(0.5);
  const Eigen::Vector3d start = PoseOf(Status()).translation();
  const JogVerdict verdict = backend_.StartJog(JogZ(200, 100));
  ASSERT_FALSE(verdict.accepted);
  EXPECT_NE(verdict.reason.find("workspace"), std::string::npos);
  Run(1.0);
  EXPECT_NEAR(MToMm((PoseOf(Status()).translation() - start).norm()), 0, 0.01);
  EXPECT_EQ(Status().state, OperatingState::kReady);
}

TEST_F(LocalSessionBackendTest, EStopLatchesUntilReset) {
  HomeToReady();
  ASSERT_TRUE(backend_.StartJog(JogZ(5, 2)).accepted);
  Run(0.5);
  ASSERT_TRUE(backend_.SendCommand(StateCommand::kEStop));
  Run(0.01);
  EXPECT_EQ(Status().state, OperatingState::kEStop);
  EXPECT_EQ(Status().fault_reason, teleop::FaultReason::kEStop);
  const double z_at_stop = PoseOf(Status()).translation().z();
  // Nothing but a reset leaves it: not enable, not home, not disable; jogs are refused.
  for (StateCommand command : {StateCommand::kEnable, StateCommand::kHome, StateCommand::kDisable}) {
    ASSERT_TRUE(backend_.SendCommand(command));
    Run(0.05);
    EXPECT_EQ(Status().state, OperatingState::kEStop) << teleop::ToString(command);
  }
  EXPECT_FALSE(backend_.StartJog(JogZ(1, 1)).accepted);
  Run(1.0);
  EXPECT_NEAR(MToMm(PoseOf(Status()).translation().z() - z_at_stop), 0, 0.2);  // the rest of the jog never ran
  // The follower unit's reset releases the latch into DISABLED (drives off until the next enable), then Home, Enable.
  ASSERT_TRUE(backend_.SendCommand(StateCommand::kReset));
  Run(0.05);
  EXPECT_EQ(Status().state, OperatingState::kDisabled);
  EXPECT_EQ(Status().fault_reason, teleop::FaultReason::kNone);
  HomeToReady();
  // The panel's leader side re-synchronised to where the robot stopped: a new jog runs from there.
  ASSERT_TRUE(backend_.StartJog(JogZ(1, 1)).accepted);
  Run(1.5);
  EXPECT_NEAR(MToMm(PoseOf(Status()).translation().z() - z_at_stop), 1, 0.1);
  EXPECT_EQ(Status().state, OperatingState::kReady);
}

TEST_F(LocalSessionBackendTest, StopEndsAJogWhereItIs) {
  HomeToReady();
  const double z0 = PoseOf(Status()).translation().z();
  ASSERT_TRUE(backend_.StartJog(JogZ(10, 4)).accepted);
  Run(1.0);
  backend_.StopJog();
  Run(1.5);
  const double moved_mm = MToMm(PoseOf(Status()).translation().z() - z0);
  EXPECT_GT(moved_mm, 0.5);
  EXPECT_LT(moved_mm, 5);  // eq. 9 at a quarter of the move: 10 · (1 - cos(pi/4)) / 2 = 1.46 mm
  EXPECT_EQ(Status().state, OperatingState::kReady);
}

TEST_F(LocalSessionBackendTest, HapticModeIsRefusedWithoutAHapticDevice) {
  HomeToReady();
  std::string reason;
  EXPECT_FALSE(backend_.RequestHapticMode(Haptic(true, false, "proxy-safe", 2), reason));
  EXPECT_NE(reason.find("no haptic device"), std::string::npos) << reason;
  Run(0.05);
  EXPECT_EQ(Status().state, OperatingState::kReady);
}

TEST_F(LocalSessionBackendTest, HapticModeRunsTheLeaderUnitWithTheSimulatedSigma7AndClutches) {
  AttachLeader("sim");
  HomeToReady();
  std::string reason;
  EXPECT_FALSE(backend_.RequestHapticMode(Haptic(true, false, "no-such-method", 2), reason));
  ASSERT_TRUE(backend_.RequestHapticMode(Haptic(true, false, "proxy-safe", 2), reason)) << reason;
  const std::uint64_t accepted_before = backend_.follower_counters().setpoints_accepted;
  Run(1.0);
  // The simulated hand holds the presence button: the leader unit's set-points make the follower follow.
  EXPECT_EQ(Status().state, OperatingState::kEnabled);
  teleop::LeaderTickRecord record;
  ASSERT_TRUE(backend_.ReadLeaderRecord(record));
  EXPECT_EQ(record.leader_state, static_cast<std::uint8_t>(teleop::LeaderState::kTracking));
  EXPECT_GE(backend_.follower_counters().setpoints_accepted - accepted_before, 900u);  // 1 s of 1 kHz set-points
  EXPECT_EQ(backend_.follower_counters().setpoints_rejected, 0u);
  EXPECT_GT(std::hypot(record.p_OH[0] - sigma7_.p_center_O().x(), record.p_OH[1] - sigma7_.p_center_O().y()),
            MmToM(5));  // the hand has moved along its circle
  EXPECT_FALSE(backend_.StartJog(JogZ(1, 1)).accepted);  // the leader owns the robot now

  // A new method or new caps need the clutch; while clutched the follower holds and no force is displayed.
  EXPECT_FALSE(backend_.RequestHapticMode(Haptic(true, false, "proxy-safe", 10), reason));
  EXPECT_NE(reason.find("clutched"), std::string::npos) << reason;
  ASSERT_TRUE(backend_.RequestHapticMode(Haptic(true, true, "proxy-safe", 2), reason)) << reason;
  Run(0.2);
  EXPECT_EQ(Status().state, OperatingState::kClutched);
  EXPECT_EQ(HandForceN(), 0.0);
  const Eigen::Vector3d held = PoseOf(Status()).translation();
  ASSERT_TRUE(backend_.RequestHapticMode(Haptic(true, true, "proxy", 10), reason)) << reason;
  Run(0.5);
  EXPECT_EQ(Status().state, OperatingState::kClutched);
  EXPECT_LT(MToMm((PoseOf(Status()).translation() - held).norm()), 0.05);  // the hand moves, the robot does not
  // A second change while clutched: each leader unit is a leader session of its own (a reused one would make the
  // new unit's restarted sequence numbers look out of order to the follower).
  ASSERT_TRUE(backend_.RequestHapticMode(Haptic(true, true, "proxy", 5), reason)) << reason;
  Run(0.2);
  ASSERT_TRUE(backend_.RequestHapticMode(Haptic(true, false, "proxy", 5), reason)) << reason;
  Run(0.5);
  EXPECT_EQ(Status().state, OperatingState::kEnabled);
  EXPECT_EQ(backend_.follower_counters().setpoints_rejected, 0u);

  // Off: the jog player holds again where the hand left the robot, and jogs run from there.
  ASSERT_TRUE(backend_.RequestHapticMode(HapticModeRequest{}, reason)) << reason;
  Run(0.2);
  EXPECT_EQ(Status().state, OperatingState::kReady);
  EXPECT_EQ(HandForceN(), 0.0);
  const double z0 = PoseOf(Status()).translation().z();
  ASSERT_TRUE(backend_.StartJog(JogZ(1, 1)).accepted);
  Run(1.5);
  EXPECT_NEAR(MToMm(PoseOf(Status()).translation().z() - z0), 1, 0.1);

  // On again: a new leader unit from where the jog left the robot.
  ASSERT_TRUE(backend_.RequestHapticMode(Haptic(true, false, "proxy-safe", 2), reason)) << reason;
  Run(0.5);
  EXPECT_EQ(Status().state, OperatingState::kEnabled);
  EXPECT_EQ(backend_.follower_counters().setpoints_rejected, 0u);
}

// A hand script (the replay format: the RSR pose the hand commands, mm and deg) that pushes straight up (+z, toward
// the nearest wall, 71 mm above home) at 9 mm/s until the sigma.7's own travel stops it, and rests there.
std::filesystem::path WriteWallPushScript(const robot::RsrModel& model) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("robossis_panel_wall_push_" + std::to_string(getpid()) + ".csv");
  const Eigen::Vector3d home = model.geometry().X_FM_home.translation();
  std::ofstream out(file);
  out << "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n";
  for (int k = 0; k <= 100; ++k) {
    const double t = 0.1 * k;                     // 10 s
    const double z_mm = 9.0 * std::min(t, 5.0);  // 9 mm/s for 5 s: 45 mm, then held
    out << t << "," << MToMm(home.x()) << "," << MToMm(home.y()) << "," << MToMm(home.z()) + z_mm << ",0,0,0\n";
  }
  return file;
}

TEST_F(LocalSessionBackendTest, TheHandPushingIntoAWallFeelsTheRenderedForce) {
  const std::filesystem::path script = WriteWallPushScript(model_);
  AttachLeader("replay:" + script.string());
  HomeToReady();
  // The sigma.7's handle travels ~15 mm up from its centre: first a jog to 9 mm below the wall (eq. 9 at the
  // follower's 10 mm/s cap), then the hand pushes the rest of the way, and beyond.
  const double z_home = PoseOf(Status()).translation().z();
  ASSERT_TRUE(backend_.StartJog(JogZ(62, 10)).accepted);
  Run(10.5);
  ASSERT_NEAR(MToMm(PoseOf(Status()).translation().z() - z_home), 62, 0.5);
  std::string reason;
  ASSERT_TRUE(backend_.RequestHapticMode(Haptic(true, false, "proxy-safe", 10), reason)) << reason;
  double max_force_n = 0;
  for (int k = 0; k < 100 && max_force_n < 1.0; ++k) {  // up to 10 s
    Run(0.1);
    max_force_n = std::max(max_force_n, HandForceN());
  }
  std::filesystem::remove(script);
  EXPECT_GT(max_force_n, 1.0);  // the wall pushes back on the hand (the arrows and the force plot show it)
  teleop::LeaderTickRecord record;
  ASSERT_TRUE(backend_.ReadLeaderRecord(record));
  EXPECT_GT(std::hypot(record.f_O[0], record.f_O[1], record.f_O[2]), 0.0);
  // The leader sent only feasible set-points: the robot stopped at the boundary, inside the workspace. (The proxy's
  // stop at the wall can break the follower's acceleration cap for a set-point or two, which the follower refuses
  // and holds through: that is the runtime's leader, measured here, not the panel's.)
  EXPECT_EQ(backend_.follower_counters().setpoints_by_verdict[static_cast<int>(teleop::SetPointVerdict::kInfeasible)],
            0u);
  // The robot rests on the wall: on the boundary, up to the simulated drives' tracking (the Bullet RSR may settle a
  // few micrometres past a stroke limit, which the follower counts in limit_violations; 10 µm is the bound here).
  const robot::RsrIkResult ik = robot::CalcInverseKinematics(model_, PoseOf(Status()));
  double min_margin = std::numeric_limits<double>::infinity();
  for (const robot::RsrLimitCheck& check : ik.checks) min_margin = std::min(min_margin, check.margin);
  EXPECT_GT(min_margin, -1e-5);
  EXPECT_LT(min_margin, 1e-3);  // and it is at the wall, not short of it
}

TEST_F(LocalSessionBackendTest, TheTickAllocatesNothingInHapticModeEither) {
  AttachLeader("sim");
  HomeToReady();
  std::string reason;
  ASSERT_TRUE(backend_.RequestHapticMode(Haptic(true, false, "proxy-safe", 2), reason)) << reason;
  Run(0.05);  // the leader unit's first ticks anchor the renderer and the transfer
  testing::AllocationCounter counter;
  Run(0.3);
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_EQ(Status().state, OperatingState::kEnabled);
}

TEST_F(LocalSessionBackendTest, TheTickAllocatesNothing) {
  HomeToReady();
  ASSERT_TRUE(backend_.StartJog(JogZ(5, 1)).accepted);
  backend_.SendCommand(StateCommand::kEnable);  // queued before counting: pushing is the panel thread's work
  testing::AllocationCounter counter;
  Run(0.3);  // takes the jog, runs it, takes the command
  EXPECT_EQ(counter.count(), 0u);
}

}  // namespace
}  // namespace robossis::panel
