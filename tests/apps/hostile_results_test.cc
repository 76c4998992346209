// Results that used to be wrong with exit 0, and nothing said so: values no robot or hand reaches accepted as
// poses, results at infeasible poses printed without a word, one rotation judged two ways, an all-equal time axis
// that moves nothing, bounds printed other than as written, unknown commands not named, and an interrupted run's
// staging folder left behind. Each runs the robossis binary as a user would.

#include <signal.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "src/core/child_process.h"
#include "tests/support/hostile_cli_test.h"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;
using robossis::testing::CommandRun;
using robossis::testing::Robossis;

class HostileResultsTest : public robossis::testing::HostileCliTest {};

// --- Poses: a value far outside any workspace is refused with its bound, whatever the command ---------------------

TEST_F(HostileResultsTest, PosesFarOutsideAnyWorkspaceAreRefusedWithTheBound) {
  ExpectError(Robossis("workspace query --live --pose 1e300,0,284,0,0,0"),
              "--pose: X_MM is '1e300'; expected a position within +-1000 mm");
  ExpectError(Robossis("workspace query --live --pose 0,0,284,1e300,0,0"),
              "--pose: ROLL_DEG is '1e300'; expected an angle within +-3600 deg");
  ExpectError(Robossis("robot ik --pose 0,0,1001,0,0,0"), "--pose: Z_MM is '1001'");
  ExpectError(Robossis("robot fk --joints 0,0,0,10000,10000,10000"),
              "--joints: D1_MM is '10000'; expected a position within +-1000 mm");
  ExpectError(Robossis("hc ik --position 0,0,0 --rpy-deg 0,3601,0"), "--rpy-deg: PITCH_DEG is '3601'");
  // The bounds themselves are values (what is reachable is the kinematics' answer).
  EXPECT_EQ(Robossis("robot ik --pose 0,0,1000,0,0,0").exit_code, 0);
}

TEST_F(HostileResultsTest, AScenarioSampleFarOutsideIsRefusedNamingTheCell) {
  const fs::path csv = Write("far.csv",
                             "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n0,0,0,284,0,0,0\n"
                             "0.5,1e300,0,284,0,0,0\n1,0,0,284,0,0,0\n");
  ExpectError(Robossis("render-compare --scenario " + Q(csv) + " --methods proxy --out " + Q(dir_ / "out")),
              "far.csv line 3, column 2 (x_mm): got '1e300'; expected a position within +-1000 mm");
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

// --- Results at poses the robot cannot reach: computed, and said to be so ----------------------------------------

TEST_F(HostileResultsTest, JacobianAndStaticsAtAnInfeasiblePoseSaySo) {
  const std::string pose = " --pose 1000,0,500,0,0,0";
  for (const std::string& cmd : {"robot jacobian" + pose, "robot statics" + pose + " --wrench 0,0,10,0,0,0"}) {
    const CommandRun text = Robossis(cmd);
    EXPECT_EQ(text.exit_code, 0) << text.output;
    EXPECT_THAT(text.output, HasSubstr("feasible: false (outside the joint limits")) << cmd;
    EXPECT_THAT(text.output, HasSubstr("violation: arm 1 stroke")) << cmd;
    const CommandRun json = Robossis(cmd + " --json", false);
    ASSERT_EQ(json.exit_code, 0) << json.output;
    const nlohmann::json j = nlohmann::json::parse(json.output);
    EXPECT_FALSE(j.at("feasible").get<bool>()) << cmd;
    EXPECT_FALSE(j.at("violations").empty()) << cmd;
  }
  const nlohmann::json home = nlohmann::json::parse(Robossis("robot statics --pose 0,0,284,0,0,0 "
                                                             "--wrench 0,0,10,0,0,0 --json", false).output);
  EXPECT_TRUE(home.at("feasible").get<bool>());
  EXPECT_TRUE(home.at("violations").empty());
}

TEST_F(HostileResultsTest, ForwardKinematicsOutsideTheStrokesSaysSo) {
  const CommandRun outside = Robossis("robot fk --joints 0,0,0,500,500,500");
  EXPECT_EQ(outside.exit_code, 0) << outside.output;
  EXPECT_THAT(outside.output, HasSubstr("feasible: false"));
  EXPECT_THAT(outside.output, HasSubstr("violation: arm 1 stroke = 500.000 mm, limit 354.000 mm"));
  const CommandRun inside = Robossis("robot fk --joints 0,0,0,284,290,300 --json", false);
  ASSERT_EQ(inside.exit_code, 0) << inside.output;
  EXPECT_TRUE(nlohmann::json::parse(inside.output).at("feasible").get<bool>());
}

TEST_F(HostileResultsTest, OneRotationIsOneWristVerdict) {
  // Pitch 300 deg and pitch -60 deg are the same rotation of the handle.
  const nlohmann::json a = nlohmann::json::parse(Robossis("hc ik --position 0,0,0 --rpy-deg 0,300,0 --json", false).output);
  const nlohmann::json b = nlohmann::json::parse(Robossis("hc ik --position 0,0,0 --rpy-deg 0,-60,0 --json", false).output);
  EXPECT_EQ(a.at("wrist_within_range"), b.at("wrist_within_range"));
  EXPECT_NEAR(a.at("wrist_rpy_deg")[1].get<double>(), -60.0, 1e-9);
}

// --- Time axes ---------------------------------------------------------------------------------------------------

TEST_F(HostileResultsTest, AnHcFileWhoseTimesAreAllEqualIsRefused) {
  const fs::path csv = Write("equal.csv",
                             "time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n1,0,0,0,0,0,0\n1,1,0,0,0,0,0\n"
                             "1,2,0,0,0,0,0\n");
  ExpectError(Robossis("transfer --hc " + Q(csv) + " --out " + Q(dir_ / "out")), "every time_s is 1");
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(HostileResultsTest, ATimeBoundIsPrintedAsTheFileWroteIt) {
  const fs::path csv = Write("repeat.csv",
                             "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n0,0,0,284,0,0,0\n"
                             "0.99,0,0,284,0,0,0\n0.99,0,0,284,0,0,0\n");
  const CommandRun run = Robossis("render-compare --scenario " + Q(csv) + " --methods proxy --out " + Q(dir_ / "o"));
  ExpectError(run, "got '0.99'; expected a time greater than 0.99 (the previous row's)");
  EXPECT_THAT(run.output, Not(HasSubstr("0.98999")));
}

TEST_F(HostileResultsTest, AnInfiniteDurationNamesTheBound) {
  ExpectError(Robossis("move --duration-s inf --delta-mm 1,0,0 --out " + Q(dir_ / "mv")),
              "--duration-s: expected a finite duration in (0, 3600] s, got inf");
}

// --- Commands -------------------------------------------------------------------------------------------------------

TEST_F(HostileResultsTest, AnUnknownCommandIsNamed) {
  ExpectError(Robossis("bogus"), "unknown command 'bogus' for 'robossis'; expected one of: robot, hc,");
  ExpectError(Robossis("robot bogus"), "unknown command 'bogus' for 'robossis robot'; expected one of: info, ik,");
  ExpectError(Robossis("robot"), "A subcommand is required");  // nothing unknown: CLI11's own words
}

// --- An interrupted run leaves nothing behind ---------------------------------------------------------------------

TEST_F(HostileResultsTest, AnInterruptedRunLeavesNoStagingFolder) {
  // A two-minute hand motion: the run is still working when the signal comes.
  std::string csv = "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n";
  for (int k = 0; k <= 12000; ++k) csv += std::to_string(k * 0.01) + "," + std::to_string(k % 200 * 0.1) + ",0,284,0,0,0\n";
  const fs::path scenario = Write("long.csv", csv);
  for (const int signal : {SIGINT, SIGTERM}) {
    SCOPED_TRACE(strsignal(signal));
    const fs::path out = dir_ / ("out_" + std::to_string(signal));
    // Started directly (not from a shell's background, which would ignore SIGINT): the signals' default actions,
    // as a terminal's Ctrl-C finds them.
    robossis::ChildProcess run(ROBOSSIS_BINARY, {"render-compare", "--scenario", scenario.string(), "--out", out.string()},
                               dir_ / "run.log");
    const fs::path staging = out.string() + ".partial-" + std::to_string(run.pid());
    bool writing = false;  // signalled once the run writes its output: its staging folder exists
    for (int i = 0; i < 6000 && !writing && run.running(); ++i) {
      writing = fs::exists(staging);
      if (!writing) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ASSERT_TRUE(writing) << Read(dir_ / "run.log");
    run.Signal(signal);
    const robossis::ChildExit exit = run.Wait();
    EXPECT_FALSE(exit.exited) << exit.Describe();
    EXPECT_EQ(exit.signal, signal) << exit.Describe();
    EXPECT_FALSE(fs::exists(staging));
    EXPECT_FALSE(fs::exists(out));
  }
}

}  // namespace
