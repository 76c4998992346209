// The panel window under Xvfb (Mesa's software renderer), driven by scripts as a person would drive it. Each test
// runs `xvfb-run -a robossis panel ...`: xvfb-run starts a private X server and always stops it when the panel
// exits; `timeout` bounds a hung run. The scripts wait for the homing and for a jog's end (`wait`) rather than give
// them a fixed time: a loaded machine only makes a run longer.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "robot/rsr_model.h"
#include "src/core/config.h"
#include "src/core/units.h"
#include "tests/panel/panel_run.h"

namespace {

using robossis::testing::PanelRun;
using robossis::testing::RunPanel;
using robossis::testing::TestDir;

double HomeZmm() {
  const robossis::robot::RsrModel model =
      robossis::robot::RsrModel::FromYaml(robossis::DefaultDataDir() / "config" / "rsr.yaml");
  return robossis::MToMm(model.geometry().X_FM_home.translation().z());
}

TEST(PanelWindow, AScriptedJogMovesTheSimulatedFollowerByTheRequestedAmount) {
  const auto dir = TestDir("jog");
  const PanelRun run = RunPanel(dir,
                                "0.2 click home\n"
                                "0.2 click enable\n"
                                "0.2 wait state ready\n"
                                "0.8 set jog.axis z\n"
                                "0.8 set jog.amount 5\n"
                                "0.8 set jog.timing duration\n"
                                "0.8 set jog.duration_s 1\n"
                                "1.0 click jog.go\n"
                                "1.0 wait jog.done\n"
                                "1.2 quit\n",
                                "--no-slice");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  ASSERT_FALSE(run.json.is_discarded()) << run.output;
  EXPECT_EQ(run.json["state"], "ready");
  EXPECT_EQ(run.json["message"], "");
  const auto pose = run.json["pose_mm_deg"];
  EXPECT_NEAR(pose[2].get<double>() - HomeZmm(), 5.0, 0.1) << run.output;
  EXPECT_NEAR(pose[0].get<double>(), 0.0, 0.1);
  EXPECT_NEAR(pose[1].get<double>(), 0.0, 0.1);
  EXPECT_GT(run.json["setpoints_accepted"].get<int>(), 0);
}

TEST(PanelWindow, ARefusedMoveLeavesTheRobotStill) {
  const auto dir = TestDir("refused");
  const PanelRun run = RunPanel(dir,
                                "0.2 click home\n"
                                "0.2 click enable\n"
                                "0.2 wait state ready\n"  // else the jog is refused for not being homed
                                "0.8 set jog.axis z\n"
                                "0.8 set jog.amount 200\n"
                                "0.8 set jog.duration_s 100\n"
                                "1.0 click jog.go\n"
                                "2.5 quit\n",
                                "--no-slice --no-bone");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.json["state"], "ready");
  EXPECT_NE(run.json["message"].get<std::string>().find("leaves the workspace"), std::string::npos) << run.output;
  // The panel's leader side sends hold set-points without presence (the follower accepts them and holds); the
  // refused jog sent none of its own, so nothing was rejected and the robot stayed at home.
  EXPECT_EQ(run.json["setpoints_rejected"].get<int>(), 0);
  EXPECT_NEAR(run.json["pose_mm_deg"][2].get<double>(), HomeZmm(), 0.05);
}

TEST(PanelWindow, TheEStopLatches) {
  const auto dir = TestDir("estop");
  const PanelRun run = RunPanel(dir,
                                "0.2 click home\n"
                                "0.2 click enable\n"
                                "0.2 wait state ready\n"
                                "0.8 set jog.amount 10\n"
                                "0.8 set jog.duration_s 4\n"
                                "1.0 click jog.go\n"
                                "1.8 click estop\n"
                                "2.2 click enable\n"
                                "2.4 click home\n"
                                "2.6 click jog.go\n"
                                "3.5 quit\n",
                                "--no-slice --no-bone");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.json["state"], "estop");
  EXPECT_EQ(run.json["fault_reason"], "estop");
  EXPECT_NE(run.json["message"].get<std::string>().find("estop"), std::string::npos) << run.output;
  const double moved_mm = run.json["pose_mm_deg"][2].get<double>() - HomeZmm();
  EXPECT_GT(moved_mm, 0.1);  // the jog had started
  EXPECT_LT(moved_mm, 9.0);  // and was stopped before its end
}

TEST(PanelWindow, HapticModeCapsChangeOnlyWhileClutched) {
  const auto dir = TestDir("haptic");
  const PanelRun run = RunPanel(dir,
                                "0.2 click home\n"
                                "0.2 click enable\n"
                                "0.2 wait state ready\n"
                                "0.8 click haptic.on\n"
                                "1.0 set haptic.caps demonstration\n"  // refused: not clutched
                                "1.2 click haptic.clutch\n"
                                "1.4 set haptic.method proxy\n"
                                "1.6 set haptic.caps demonstration\n"
                                "2.5 quit\n",
                                "--no-slice --no-bone");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  // Clutched (the follower holds), or holding for a tick because the leader side's set-point came late on a loaded
  // machine (ready); the exact state sequence is LocalSessionBackendTest's, in simulated time.
  const std::string state = run.json["state"];
  EXPECT_TRUE(state == "clutched" || state == "ready") << state;
  EXPECT_EQ(run.json["haptic"]["caps"], "demonstration");
  EXPECT_EQ(run.json["haptic"]["method"], "proxy");
  EXPECT_TRUE(run.json["haptic"]["clutched"].get<bool>());
}

// Haptic mode with the simulated sigma.7: a jog takes the robot to 5 mm below the nearest wall (71 mm above home),
// then in haptic mode the hand (a replay script, the RSR pose it commands) pushes on up, beyond the wall, as far as
// the sigma.7's handle travels; the panel shows the rendered force on the hand and the robot stops at the wall.
// The demonstration caps are chosen while clutched, so the robot follows the hand within the run.
// The replay starts at the device's first read (haptic.on) and holds the hand still for its first 5 s: choosing the
// caps rebuilds the leader, which stalls the window's frame (1.2 to 1.9 s measured under AddressSanitizer), and the
// hand must not have used up its travel before the unclutch, or it can no longer push beyond the wall.
TEST(PanelWindow, HapticModeShowsTheForceOfTheWallTheHandPushesInto) {
  const auto dir = TestDir("haptic_wall");
  const robossis::robot::RsrModel model =
      robossis::robot::RsrModel::FromYaml(robossis::DefaultDataDir() / "config" / "rsr.yaml");
  const Eigen::Vector3d home = model.geometry().X_FM_home.translation();
  const std::filesystem::path hand = dir / "wall_push.csv";
  {
    std::ofstream out(hand);
    out << "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n";
    for (int k = 0; k <= 150; ++k) {  // 15 s: still for 5 s, 9 mm/s up for 5 s, then held there
      const double t = 0.1 * k;
      out << t << "," << robossis::MToMm(home.x()) << "," << robossis::MToMm(home.y()) << ","
          << robossis::MToMm(home.z()) + 9.0 * std::clamp(t - 5.0, 0.0, 5.0) << ",0,0,0\n";
    }
  }
  const PanelRun run = RunPanel(dir,
                                "0.2 click home\n"
                                "0.2 click enable\n"
                                "0.2 wait state ready\n"
                                "0.8 set jog.axis z\n"
                                "0.8 set jog.amount 66\n"
                                "0.8 set jog.duration_s 11\n"  // eq. 9 peak 9.4 mm/s, under the 10 mm/s cap
                                "0.9 click jog.go\n"
                                "0.9 wait jog.done\n"  // the script's clock stands still until the jog's end
                                "1.0 click haptic.on\n"
                                "1.0 click haptic.clutch\n"
                                "1.1 set haptic.caps demonstration\n"
                                "1.2 click haptic.unclutch\n"
                                "13.5 quit\n",  // the hand's 10 s, and room for a loaded machine's late loops
                                "--no-slice --no-bone --device replay:" + hand.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.json["haptic"]["caps"], "demonstration");
  EXPECT_TRUE(run.json["haptic"]["enabled"].get<bool>());
  EXPECT_FALSE(run.json["haptic"]["clutched"].get<bool>());
  // Powered and following (enabled), or holding for a tick because a set-point came late on a loaded machine
  // (ready); never a fault, a disable or a lost leader.
  const std::string state = run.json["state"];
  EXPECT_TRUE(state == "enabled" || state == "ready") << state;
  EXPECT_EQ(run.json["fault_reason"], "none");
  EXPECT_GT(run.json["haptic"]["max_hand_force_n"].get<double>(), 1.0) << run.output;
  const double z_mm = run.json["pose_mm_deg"][2].get<double>() - robossis::MToMm(home.z());
  EXPECT_GT(z_mm, 66.5);  // it followed the hand up from the jog's end ...
  EXPECT_LT(z_mm, 71.5);  // ... and stopped at the wall
}

// `--link dds`: the panel joins the link as its own participant (here --insecure, on a domain of this process, with
// no follower on it): it shows no status, its E-stop is still queued to the link, and haptic mode is refused
// because the panel may not publish set-points. (The exchange with a follower unit: panel_dds_test.)
TEST(PanelWindow, OverTheDdsLinkThePanelCommandsButRefusesHapticMode) {
  const auto dir = TestDir("dds");
  const PanelRun run = RunPanel(dir, "0.3 click estop\n0.5 click haptic.on\n1.0 quit\n",
                                "--no-slice --no-bone --link dds --insecure --domain " +
                                    std::to_string(1 + getpid() % 200));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.json["link"], "dds");
  EXPECT_FALSE(run.json["haptic"]["enabled"].get<bool>());
  EXPECT_NE(run.json["message"].get<std::string>().find("set-points"), std::string::npos) << run.output;
}

TEST(PanelWindow, AnUnknownScriptActionIsAnErrorNamingTheLine) {
  const auto dir = TestDir("unknown");
  const PanelRun run = RunPanel(dir, "0.1 click nothing.here\n1.0 quit\n", "--no-slice --no-bone");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find("robossis: error: --script line 1"), std::string::npos) << run.output;
}

TEST(PanelWindow, ScreenshotsAreNotBlankAndShowTheRobot) {
  const auto dir = TestDir("screenshot");
  const std::string shot = (dir / "panel.png").string();
  const std::string mid = (dir / "mid.png").string();
  const PanelRun run = RunPanel(dir, "0.2 click home\n1.5 screenshot " + mid + "\n2.0 quit\n",
                                "--width 1600 --height 900 --screenshot " + shot);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  ASSERT_EQ(run.json["screenshots"].size(), 2u);
  for (const std::string& path : {mid, shot}) {
    const cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
    ASSERT_FALSE(image.empty()) << path;
    EXPECT_EQ(image.cols, 1600);
    EXPECT_EQ(image.rows, 900);
    cv::Scalar mean, stddev;
    cv::meanStdDev(image, mean, stddev);
    EXPECT_GT(stddev[0] + stddev[1] + stddev[2], 30) << "a blank screenshot: " << path;
    // The robot view (between the controls and the numbers) holds the moving ring's colour (240, 190, 60 RGB)
    // and the arms' (120, 220, 140 RGB).
    int ring = 0, arm = 0, bone = 0;
    for (int r = 64; r < image.rows; ++r) {
      for (int c = 380; c < image.cols - 540; ++c) {
        const cv::Vec3b bgr = image.at<cv::Vec3b>(r, c);
        auto near = [&](int R, int G, int B) {
          return std::abs(bgr[2] - R) < 12 && std::abs(bgr[1] - G) < 12 && std::abs(bgr[0] - B) < 12;
        };
        ring += near(240, 190, 60);
        arm += near(120, 220, 140);
        bone += bgr[2] > 150 && bgr[1] > 120 && bgr[0] > 90 && bgr[2] >= bgr[0] + 20;  // bone tones
      }
    }
    EXPECT_GT(ring, 200) << path;
    EXPECT_GT(arm, 200) << path;
    EXPECT_GT(bone, 500) << path;
  }
}

}  // namespace
