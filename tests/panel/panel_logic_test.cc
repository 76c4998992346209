// The panel's logic without a window: jog preview (eq. 9 path against the joint limits), haptic-mode rules, the
// script parser, the plot ring, the view model.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "robot/follower.h"
#include "robot/rsr_kinematics.h"
#include "src/core/config.h"
#include "src/core/pose.h"
#include "src/core/units.h"
#include "src/panel/haptic_mode.h"
#include "src/panel/jog.h"
#include "src/panel/plot_buffer.h"
#include "src/panel/script.h"
#include "src/panel/view_model.h"

namespace robossis::panel {
namespace {

robot::RsrModel Model() { return robot::RsrModel::FromYaml(DefaultDataDir() / "config" / "rsr.yaml"); }

TEST(JogPreview, AcceptsAnInsideMoveAndReportsItsEndPose) {
  const robot::RsrModel model = Model();
  const Eigen::Isometry3d home = model.geometry().X_FM_home;
  JogRequest request;
  request.axis = JogAxis::kZ;
  request.amount = MmToM(5);
  request.duration_s = 2;
  const JogVerdict verdict = PreviewJog(model, home, request, JogLimits{});
  ASSERT_TRUE(verdict.accepted) << verdict.reason;
  EXPECT_NEAR((verdict.X_FM_end.translation() - home.translation()).z(), 0.005, 1e-12);
  EXPECT_NEAR(verdict.peak_speed, kPi / 2 * 0.005 / 2, 1e-12);  // eq. 9 peak: pi/2 · dx / dt
  EXPECT_GE(verdict.tightest.margin, 0);
}

TEST(JogPreview, RefusesAMoveThatLeavesTheWorkspaceAndSaysWhichLimit) {
  const robot::RsrModel model = Model();
  JogRequest request;
  request.axis = JogAxis::kZ;
  request.amount = MmToM(200);  // far beyond the stroke
  request.duration_s = 100;
  const JogVerdict verdict = PreviewJog(model, model.geometry().X_FM_home, request, JogLimits{});
  EXPECT_FALSE(verdict.accepted);
  EXPECT_NE(verdict.reason.find("leaves the workspace"), std::string::npos) << verdict.reason;
  EXPECT_LT(verdict.tightest.margin, 0);
}

TEST(JogPreview, RefusesAMoveFasterThanTheCap) {
  const robot::RsrModel model = Model();
  JogRequest request;
  request.axis = JogAxis::kYaw;
  request.amount = DegToRad(5);
  request.duration_s = 1;  // peak pi/2 · 5 deg/s > 1 deg/s
  const JogVerdict verdict = PreviewJog(model, model.geometry().X_FM_home, request, JogLimits{});
  EXPECT_FALSE(verdict.accepted);
  EXPECT_NE(verdict.reason.find("exceeds the cap"), std::string::npos) << verdict.reason;
}

TEST(JogPreview, RefusesAMoveShorterThanOneActuationTickWhateverItsEndPose) {
  // The check `robossis move` uses: a jog that would change the pose within one tick has no sample inside it.
  const robot::RsrModel model = Model();
  JogRequest request;
  request.axis = JogAxis::kZ;
  request.amount = MmToM(1e-4);
  request.duration_s = 1e-6;  // under one 10 kHz tick
  JogLimits limits;
  limits.setpoint.caps.max_linear_speed_m_s = 1e9;  // so that only the length can refuse it
  const JogVerdict verdict = PreviewJog(model, model.geometry().X_FM_home, request, limits);
  EXPECT_FALSE(verdict.accepted);
  EXPECT_NE(verdict.reason.find("less than one actuation tick"), std::string::npos) << verdict.reason;
  request.amount = MmToM(200);  // and far beyond the stroke: the path check names the workspace first
  const JogVerdict far = PreviewJog(model, model.geometry().X_FM_home, request, limits);
  EXPECT_FALSE(far.accepted);
  EXPECT_NE(far.reason.find("leaves the workspace"), std::string::npos) << far.reason;
}

TEST(JogPreview, SpeedTimingGivesTheEq9Interval) {
  JogRequest request;
  request.axis = JogAxis::kX;
  request.amount = MmToM(-4);
  request.timing = JogTiming::kSpeed;
  request.peak_speed = MmToM(2);
  EXPECT_NEAR(JogDuration(request), kPi / 2 * 4 / 2, 1e-12);  // eq. 9: dt = pi/2 · |dx| / v
  request.peak_speed = 0;
  EXPECT_THROW(JogDuration(request), std::invalid_argument);
}

TEST(JogAxis, NamesRoundTripAndUnknownNamesAreRefused) {
  for (JogAxis axis : {JogAxis::kX, JogAxis::kY, JogAxis::kZ, JogAxis::kRoll, JogAxis::kPitch, JogAxis::kYaw})
    EXPECT_EQ(JogAxisFromString(ToString(axis)), axis);
  EXPECT_THROW(JogAxisFromString("w"), std::invalid_argument);
}

TEST(HapticMode, CapChangesOnlyWhileClutched) {
  HapticModeModel mode({"pointcloud", "proxy"}, {0.010, DegToRad(1)});
  std::string reason;
  EXPECT_EQ(mode.cap_preset(), SpeedCapPreset::kClinical);
  EXPECT_NEAR(mode.caps().max_linear_speed_m_s, 0.002, 1e-15);
  EXPECT_NEAR(mode.caps().max_angular_speed_rad_s, DegToRad(0.2), 1e-15);
  EXPECT_FALSE(mode.SetCapPreset(SpeedCapPreset::kDemonstration, reason));
  EXPECT_NE(reason.find("clutched"), std::string::npos);
  ASSERT_TRUE(mode.SetEnabled(true, reason));
  EXPECT_FALSE(mode.SetCapPreset(SpeedCapPreset::kDemonstration, reason));
  EXPECT_FALSE(mode.SetMethod("proxy", reason));  // following: the walls stay
  ASSERT_TRUE(mode.SetClutched(true, reason));
  EXPECT_TRUE(mode.SetCapPreset(SpeedCapPreset::kDemonstration, reason));
  EXPECT_TRUE(mode.SetMethod("proxy", reason));
  EXPECT_NEAR(mode.request().max_linear_speed_m_s, 0.010, 1e-15);
  EXPECT_EQ(mode.request().rendering_method, 1);
  EXPECT_FALSE(mode.SetMethod("nonsense", reason));
  ASSERT_TRUE(mode.SetEnabled(false, reason));
  EXPECT_FALSE(mode.clutched());
  EXPECT_FALSE(mode.SetClutched(true, reason));  // no clutch with haptic mode off
}

TEST(Script, ParsesTimedActionsAndSkipsComments) {
  const auto actions = ParseScript("# a jog\n0.5 set jog.axis z\n\n0.6 click jog.go  # go\n2 screenshot a.png\n3 quit\n",
                                   "s.txt");
  ASSERT_EQ(actions.size(), 4u);
  EXPECT_EQ(actions[0].verb, ScriptVerb::kSet);
  EXPECT_EQ(actions[0].target, "jog.axis");
  EXPECT_EQ(actions[0].value, "z");
  EXPECT_EQ(actions[1].verb, ScriptVerb::kClick);
  EXPECT_EQ(actions[1].line, 4);
  EXPECT_EQ(actions[2].verb, ScriptVerb::kScreenshot);
  EXPECT_EQ(actions[3].verb, ScriptVerb::kQuit);
  ScriptPlayer player(actions);
  EXPECT_EQ(player.NextDue(0.4), nullptr);
  ASSERT_NE(player.NextDue(0.7), nullptr);
  ASSERT_NE(player.NextDue(0.7), nullptr);
  EXPECT_EQ(player.NextDue(0.7), nullptr);
  EXPECT_FALSE(player.finished());
}

// A wait holds the script back until its condition holds, and the script's clock stands still meanwhile: the
// actions after it keep their spacing from the moment it was satisfied, however long that took.
TEST(Script, AWaitHoldsTheActionsAfterItAndShiftsTheirTimes) {
  const auto actions = ParseScript("0.2 click home\n0.2 wait state ready\n0.5 click jog.go\n0.5 wait jog.done 30\n"
                                   "1.0 quit\n",
                                   "s.txt");
  ASSERT_EQ(actions.size(), 5u);
  EXPECT_EQ(actions[1].verb, ScriptVerb::kWait);
  EXPECT_EQ(actions[1].target, "state");
  EXPECT_EQ(actions[1].value, "ready");
  EXPECT_DOUBLE_EQ(actions[1].timeout_s, kDefaultWaitTimeoutS);
  EXPECT_EQ(actions[3].target, "jog.done");
  EXPECT_DOUBLE_EQ(actions[3].timeout_s, 30);
  ScriptPlayer player(actions);
  ASSERT_NE(player.NextDue(0.2), nullptr);  // click home
  const ScriptAction* wait = player.NextDue(0.2);
  ASSERT_NE(wait, nullptr);
  EXPECT_EQ(wait->verb, ScriptVerb::kWait);
  EXPECT_EQ(player.NextDue(5.0), wait);  // not satisfied: returned again, the click behind it held back
  EXPECT_DOUBLE_EQ(player.WaitingS(5.0), 4.8);
  player.Satisfied(5.0);                    // 4.8 s waited: jog.go, at 0.5, is due at 5.3
  EXPECT_EQ(player.NextDue(5.2), nullptr);
  const ScriptAction* go = player.NextDue(5.301);
  ASSERT_NE(go, nullptr);
  EXPECT_EQ(go->target, "jog.go");
  const ScriptAction* done = player.NextDue(5.301);
  ASSERT_NE(done, nullptr);
  EXPECT_EQ(done->target, "jog.done");
  player.Satisfied(5.301);  // at once: nothing more waited, quit stays 0.5 s after the jog
  EXPECT_EQ(player.NextDue(5.7), nullptr);
  ASSERT_NE(player.NextDue(5.81), nullptr);
  EXPECT_TRUE(player.finished());
}

TEST(Script, AWaitNamesAKnownConditionAndAPositiveTimeout) {
  for (const char* bad : {"1 wait\n", "1 wait state\n", "1 wait state parked\n", "1 wait jog.moving\n",
                          "1 wait jog.done 0\n", "1 wait jog.done -1\n", "1 wait jog.done inf\n",
                          "1 wait jog.done 5x\n", "1 wait state ready 5 6\n"}) {
    try {
      ParseScript(bad, "s.txt");
      ADD_FAILURE() << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("s.txt:1: "), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW(ParseScript("1 wait state estop 2.5\n", "s"));
}

TEST(Script, ErrorsNameTheSourceLineAndExpectation) {
  try {
    ParseScript("0.1 click go\n0.05 quit\n", "s.txt");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("s.txt:2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParseScript("x click go\n", "s"), std::invalid_argument);
  EXPECT_THROW(ParseScript("1 jump\n", "s"), std::invalid_argument);
  EXPECT_THROW(ParseScript("1 set jog.axis\n", "s"), std::invalid_argument);
  EXPECT_THROW(ParseScript("1 quit now\n", "s"), std::invalid_argument);
}

TEST(Script, AFileThatIsNotARegularFileIsRefusedBeforeAnyRead) {
  // /dev/zero read until out of memory before, and a directory read as an empty script.
  for (const std::string& file : {std::string("/dev/zero"), ::testing::TempDir(), std::string("/nonexistent/s.txt")}) {
    try {
      LoadScript(file);
      FAIL() << file;
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("--script: ", 0), 0u) << what;
      EXPECT_NE(what.find(file.substr(0, file.find_last_not_of('/') + 1)), std::string::npos) << what;
    }
  }
}

TEST(PlotBuffer, KeepsTheNewestSamplesInOrder) {
  PlotBuffer<1> buffer(3);
  for (int i = 0; i < 5; ++i) buffer.Push(i, {static_cast<float>(10 * i)});
  ASSERT_EQ(buffer.size(), 3u);
  EXPECT_EQ(buffer.time_s(0), 2);
  EXPECT_EQ(buffer.values(2)[0], 40.f);
  buffer.TrimOlderThan(1.0);
  ASSERT_EQ(buffer.size(), 2u);
  EXPECT_EQ(buffer.time_s(0), 3);
}

TEST(ViewModel, PoseInMmDegAndGaugesMatchTheInverseKinematics) {
  const robot::RsrModel model = Model();
  const Eigen::Isometry3d X = PoseFromMmDeg((Vector6d() << 10, -5, 290, 2, -3, 4).finished());
  teleop::FollowerStatusMessage status;
  const Eigen::Quaterniond q(X.linear());
  status.p_FM = {X.translation().x(), X.translation().y(), X.translation().z()};
  status.q_FM = {q.w(), q.x(), q.y(), q.z()};
  status.state = teleop::OperatingState::kFault;
  status.fault_reason = teleop::FaultReason::kBackEnd;
  status.back_end_fault = static_cast<std::uint8_t>(robot::FollowerFault::kJointLimit);
  const PanelViewModel view = BuildViewModel(model, status);
  EXPECT_NEAR(view.pose_mm_deg[0], 10, 1e-9);
  EXPECT_NEAR(view.pose_mm_deg[2], 290, 1e-9);
  EXPECT_NEAR(view.pose_mm_deg[5], 4, 1e-9);
  EXPECT_TRUE(view.latched);
  EXPECT_NE(view.fault_text.find(robot::ToString(robot::FollowerFault::kJointLimit)), std::string::npos);
  const robot::RsrIkResult ik = robot::CalcInverseKinematics(model, X);
  for (int arm = 0; arm < 3; ++arm) {
    EXPECT_NEAR(view.gauges[3 * arm + 1].value, MToMm(ik.joints.d_m[arm]), 1e-9);
    EXPECT_NEAR(view.gauges[3 * arm + 0].value, RadToDeg(ik.joints.theta_rad[arm]), 1e-9);
    EXPECT_NEAR(view.gauges[3 * arm + 2].value, RadToDeg(ik.joints.cone_rad[arm]), 1e-9);
    EXPECT_GE(view.gauges[3 * arm + 1].fraction(), 0);
    EXPECT_LE(view.gauges[3 * arm + 1].fraction(), 1);
  }
  EXPECT_NEAR(view.gauges[1].margin, MToMm(std::min(ik.joints.d_m[0] - model.limits().stroke_min_m,
                                                    model.limits().stroke_max_m - ik.joints.d_m[0])),
              1e-9);
}

TEST(ViewModel, ARefusedEnableShowsItsReasonAndHomeIsOfferedOnlyWhileDisabled) {
  const robot::RsrModel model = Model();
  teleop::FollowerStatusMessage status;
  status.state = teleop::OperatingState::kDisabled;
  status.fault_reason = teleop::FaultReason::kNotHomed;
  PanelViewModel view = BuildViewModel(model, status);
  EXPECT_NE(view.refusal_text.find("not homed"), std::string::npos);
  EXPECT_EQ(view.fault_text, "");  // a refusal, not a fault
  EXPECT_FALSE(view.homed);
  EXPECT_TRUE(view.home_allowed);
  status.fault_reason = teleop::FaultReason::kNone;
  status.homed = true;
  for (teleop::OperatingState state : {teleop::OperatingState::kHoming, teleop::OperatingState::kReady,
                                       teleop::OperatingState::kEnabled, teleop::OperatingState::kClutched,
                                       teleop::OperatingState::kFault, teleop::OperatingState::kEStop}) {
    status.state = state;
    view = BuildViewModel(model, status);
    EXPECT_FALSE(view.home_allowed) << teleop::ToString(state);
    EXPECT_EQ(view.refusal_text, "");
  }
}

}  // namespace
}  // namespace robossis::panel
