// A whole session in simulated time: the fast hand (250 mm/s, ±60°, far outside the workspace) through every
// rendering method into the follower, with caps high enough that the set-point reaches the walls: no measured joint
// limit is ever crossed, nothing non-finite comes out, the follower follows; replaying the session log reproduces
// the summary exactly.

#include <filesystem>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "robot/follower.h"
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
