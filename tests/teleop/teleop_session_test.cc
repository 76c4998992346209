// A whole session in simulated time: the fast hand (250 mm/s, ±60°, far outside the workspace) through every
// rendering method into the follower, with caps high enough that the set-point reaches the walls: no measured joint
// limit is ever crossed, nothing non-finite comes out, the follower follows; replaying the session log reproduces
// the summary exactly.

#include <algorithm>
#include <filesystem>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "robot/follower.h"
#include "src/core/files.h"
#include "src/teleop/streamed_text_file.h"
#include "src/teleop/teleop_session.h"
#include "tests/teleop/teleop_fixture.h"

namespace robossis::teleop {
namespace {

using namespace testing;

TeleopSetup FastSetup() {
  TeleopSetup s = TeleopSetup::Load(DefaultDataDir(), Rsr(), Sigma7());
  // 100 mm/s and 20°/s: 10x and 20x the paper's caps, so the fast hand drives the set-point into every wall.
  s.transfer.caps.max_linear_speed_m_s = 0.100;
  s.transfer.caps.max_angular_speed_rad_s = 20 * 3.14159265358979 / 180;
  s.follower.setpoint.caps = s.transfer.caps;
  return s;
}

TeleopRequest FastHandRequest(const std::string& method, const std::string& follower) {
  TeleopRequest r;
  r.device = "replay:" + FastHand().string();
  r.method = method;
  r.follower = follower;
  r.duration_s = 20;
  if (method.rfind("mesh", 0) == 0) r.atlas = CoarseAtlas();
  return r;
}

class SessionEveryMethod : public ::testing::TestWithParam<std::string> {};

TEST_P(SessionEveryMethod, FastHandNeverDrivesTheFollowerPastALimit) {
  const auto log = std::filesystem::temp_directory_path() / ("robossis_session_" + GetParam() + ".rlog");
  const TeleopOutputs out = RunTeleop(FastHandRequest(GetParam(), "recorder"), FastSetup(), log);
  const auto& s = out.summary;
  EXPECT_EQ(s["follower_limit_violations"], 0);
  EXPECT_EQ(s["nonfinite_outputs"], 0);
  EXPECT_GT(s["follower_ticks"].get<double>(), 16.0 * 10000);  // the whole replay (16 s) plus the 0.5 s settle
  EXPECT_GT(s["setpoints_stopped_at_boundary"].get<double>(), 500);  // the walls were reached: the test can fail
  EXPECT_GT(s["max_follower_speed_mm_s"].get<double>(), 10.0);       // and the follower did follow
  // At the walls too, the leader's set-points stay within the follower's speed and acceleration caps: it accepts
  // every one and never holds for want of one (before the leader shaped them, 60-660 were rejected per method).
  EXPECT_EQ(s["setpoints_rejected"], 0) << s["setpoints_rejected_by_reason"].dump();
  EXPECT_EQ(s["watchdog_holds"], 0);
  EXPECT_TRUE(s["complete"].get<bool>());
  std::filesystem::remove(log);
}

INSTANTIATE_TEST_SUITE_P(Methods, SessionEveryMethod, ::testing::ValuesIn(haptics::KnownMethods()),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (char& c : n) if (c == '-') c = '_';
                           return n;
                         });

TEST(TeleopSessionTest, BulletFollowerStaysInsideAndTheLogReproducesTheSummary) {
  const auto log = std::filesystem::temp_directory_path() / "robossis_session_bullet.rlog";
  TeleopRequest r = FastHandRequest("proxy-safe", "sim");
  r.duration_s = 4;
  const TeleopOutputs run = RunTeleop(r, FastSetup(), log);
  EXPECT_EQ(run.summary["follower_limit_violations"], 0);
  EXPECT_EQ(run.summary["follower_ticks"], 40000);
  EXPECT_EQ(run.summary["leader_ticks"], 4000);
  EXPECT_GT(run.summary["max_follower_speed_mm_s"].get<double>(), 10.0);
  const TeleopOutputs replay = ReplaySessionLog(log);
  EXPECT_EQ(replay.summary, run.summary);
  EXPECT_EQ(replay.follower_csv, run.follower_csv);
  EXPECT_EQ(replay.leader_csv, run.leader_csv);
  std::filesystem::remove(log);
}

// With csv_dir the CSVs are written as the run goes (memory flat over a long run), byte for byte the ones returned
// otherwise.
TEST(TeleopSessionTest, StreamedCsvsAreTheReturnedOnes) {
  const robossis::testing::ScratchDir dir("robossis_session_streamed");
  std::filesystem::create_directories(dir.path());
  TeleopRequest r = FastHandRequest("proxy-safe", "recorder");
  r.duration_s = 3;
  const TeleopOutputs whole = RunTeleop(r, FastSetup(), dir.path() / "whole.rlog");
  r.csv_dir = dir.path();
  const TeleopOutputs streamed = RunTeleop(r, FastSetup(), dir.path() / "streamed.rlog");
  EXPECT_EQ(streamed.leader_csv, "");
  EXPECT_EQ(streamed.follower_csv, "");
  EXPECT_EQ(ReadTextFile(dir.path() / "leader.csv"), whole.leader_csv);
  EXPECT_EQ(ReadTextFile(dir.path() / "follower.csv"), whole.follower_csv);
  EXPECT_GT(whole.leader_csv.size(), 2 * kStreamedTextChunkBytes);  // several chunks were streamed
  EXPECT_EQ(streamed.summary, whole.summary);
  EXPECT_EQ(streamed.recorder_error, "");
}

// The recorder's sink fails mid-run (leader.csv on a full device, /dev/full): the follower holds, the session ends
// soon after instead of running on unrecorded, and the outputs name the cause.
TEST(TeleopSessionTest, ARecorderThatFailsEndsTheRunAndNamesTheCause) {
  const robossis::testing::ScratchDir dir("robossis_session_full");
  std::filesystem::create_directories(dir.path());
  std::filesystem::create_symlink("/dev/full", dir.path() / "leader.csv");
  TeleopRequest r = FastHandRequest("proxy-safe", "recorder");
  r.csv_dir = dir.path();
  const TeleopOutputs out = RunTeleop(r, FastSetup(), dir.path() / "session.rlog");
  EXPECT_NE(out.recorder_error.find("leader.csv: write failed: No space left on device"), std::string::npos)
      << out.recorder_error;
  EXPECT_NE(out.recorder_error.find("the follower held the robot at rest"), std::string::npos);
  EXPECT_EQ(out.summary["recorder_error"], out.recorder_error);
  EXPECT_FALSE(out.summary["complete"].get<bool>());
  // Recorded up to the failure (after ~256 KiB of leader.csv, about a second), not the replay's 16 s.
  EXPECT_GT(out.summary["follower_ticks"].get<double>(), 0);
  EXPECT_LT(out.summary["follower_ticks"].get<double>(), 5.0 * 10000);
  // follower.csv (still writable) holds what was recorded: 200 Hz rows up to the failure, not its header alone.
  const std::string follower_csv = ReadTextFile(dir.path() / "follower.csv");
  EXPECT_GT(std::count(follower_csv.begin(), follower_csv.end(), '\n'), 100);
}

// The follower units that enable at their start by default are exactly those whose back ends measure their joints
// (homed from their start); the HAL drives (not constructible without HAL) start disabled.
TEST(TeleopSessionTest, OnlyBackEndsThatMeasureTheirJointsEnableAtStartByDefault) {
  const TeleopSetup setup = TeleopSetup::Load(DefaultDataDir(), Rsr(), Sigma7());
  for (const std::string kind : {"sim", "recorder"}) {
    const std::unique_ptr<robot::Follower> back_end = MakeFollowerBackEnd(kind, setup, 1);
    EXPECT_TRUE(back_end->MeasuresJoints()) << kind;
    EXPECT_TRUE(back_end->State().homed) << kind;
    EXPECT_TRUE(EnablesAtStartByDefault(kind)) << kind;
  }
  EXPECT_FALSE(EnablesAtStartByDefault("hal"));
}

TEST(TeleopSessionTest, BadRequestsNameTheOption) {
  const auto log = std::filesystem::temp_directory_path() / "robossis_session_bad.rlog";
  TeleopRequest r;
  r.method = "nope";
  EXPECT_THROW(RunTeleop(r, FastSetup(), log), std::invalid_argument);
  r = TeleopRequest{};
  r.follower = "hal9000";
  EXPECT_THROW(RunTeleop(r, FastSetup(), log), std::invalid_argument);
  r = TeleopRequest{};
  r.rate_hz = 1500;  // not a multiple of the 1 kHz transfer
  EXPECT_THROW(RunTeleop(r, FastSetup(), log), std::invalid_argument);
}

}  // namespace
}  // namespace robossis::teleop
