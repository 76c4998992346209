// A session run as two processes writes two logs: the leader's (the load shown, with the stamp of the follower
// status it came from, as that stamp came over the link) and the follower's (the true load, on the follower's own
// clock, and the offset its link put on the stamps). Joined on the follower's clock they give the figure the
// one-process records give: feedback_force_error_n_rms, the shown load against the true one with the delay removed.

#include "src/teleop/split_session.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "src/core/units.h"
#include "src/teleop/flight_recorder.h"
#include "src/teleop/session_log.h"
#include "src/teleop/session_summary.h"
#include "tests/support/scratch_dir.h"
#include "tests/teleop/teleop_fixture.h"

namespace robossis::teleop {
namespace {

// A system clock's reading, as a DDS follower link's offset from its session clock is.
constexpr std::int64_t kSystemOffsetNs = 1'764'943'200'123'456'789;

// The two logs of a split run as RunLeader and RunFollower write them (every stream declared, each holding its own
// unit's records): the leader's (its status stamps as the link delivered them) and the follower's.
void WriteSplitLogs(const std::filesystem::path& dir, nlohmann::json leader_meta, nlohmann::json follower_meta,
                    const std::vector<LeaderTickRecord>& leader, const std::vector<FollowerTickRecord>& follower,
                    const std::vector<SessionEndRecord>& end = {}) {
  leader_meta["units"] = "leader";
  follower_meta["units"] = "follower";
  {
    SessionLogWriter log(dir / "leader.rlog", leader_meta, {LeaderStreamSpec(), FollowerStreamSpec(), EndStreamSpec()});
    for (const auto& r : leader) log.Append(kLeaderStream, &r);
    for (const auto& e : end) log.Append(kEndStream, &e);
    log.Flush();
  }
  SessionLogWriter log(dir / "follower.rlog", follower_meta, {LeaderStreamSpec(), FollowerStreamSpec(), EndStreamSpec()});
  for (const auto& r : follower) log.Append(kFollowerStream, &r);
  for (const auto& e : end) log.Append(kEndStream, &e);
  log.Flush();
}

double ForceError(const nlohmann::ordered_json& summary) {
  const auto& v = summary.at("feedback_force_error_n_rms");
  return v.is_number() ? v.get<double>() : std::nan("");
}

// Synthetic records with a known answer: the true load changes at 1000 N/s, the leader shows at 1 kHz the status
// stamped 50 ms earlier (the link's delay), mapped, with a constant 0.5 N error (0.3, 0, -0.4). One process: 0.5 N.
// The same records as two logs, the stamps on the system clock: the same 0.5 N, to the last bit. A join off by
// 1 ms (the follower's offset misread by one status period) judges each shown force against the load of another
// status and misses it by the load's change; without the offset nothing can be joined (null), so this test fails
// without the join.
TEST(SplitSessionTest, TwoLogsJoinedOnTheFollowersClockGiveTheOneProcessFigure) {
  SummaryOptions options;
  options.feedback_map_known = true;
  options.feedback_gain = 0.025;
  options.feedback_translation_scale = 2;
  options.feedback_R_FO = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d M = 0.025 * 2 * options.feedback_R_FO.transpose();
  const auto true_force = [](double t) { return Eigen::Vector3d(300 + 1000 * t, -50, 100 * t); };
  const Eigen::Vector3d error(0.3, 0, -0.4);

  std::vector<FollowerTickRecord> follower;
  for (int k = 0; k <= 20000; ++k) {  // 2 s at 10 kHz
    FollowerTickRecord f;
    f.tick = static_cast<std::uint64_t>(k + 1);
    f.time_s = 1e-4 * k;
    f.meas_time_s = f.time_s;
    f.true_load_known = true;
    const Eigen::Vector3d W = true_force(f.time_s);
    for (int i = 0; i < 3; ++i) f.true_wrench_F[i] = W[i];
    follower.push_back(f);
  }
  std::vector<LeaderTickRecord> leader;  // the one process's: stamps on the follower's clock
  for (int k = 100; k < 2000; ++k) {
    LeaderTickRecord l;
    l.t_ns = 1'000'000LL * k;
    l.follower_stamp_ns = l.t_ns - 50'000'000;
    l.feedback_shown = 1;
    const Eigen::Vector3d shown = M * true_force(1e-9 * static_cast<double>(l.follower_stamp_ns)) + error;
    for (int i = 0; i < 3; ++i) l.feedback_O[i] = l.feedback_wanted_O[i] = shown[i];
    leader.push_back(l);
  }
  SessionSummary one_process(options);
  for (const auto& l : leader) one_process.AddLeader(l);
  for (const auto& f : follower) one_process.AddFollower(f);
  const double expected = ForceError(one_process.Summary());
  ASSERT_NEAR(expected, 0.5, 1e-9);

  std::vector<LeaderTickRecord> over_dds = leader;  // as the DDS link delivers them: on the follower's system clock
  for (auto& l : over_dds) l.follower_stamp_ns += kSystemOffsetNs;
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> R = options.feedback_R_FO;
  const nlohmann::json leader_meta = {{"rate_hz", 1000}, {"follower_rate_hz", 10000}, {"feedback_gain", 0.025},
                                      {"feedback_translation_scale", 2},
                                      {"feedback_R_FO", std::vector<double>(R.data(), R.data() + 9)}};
  const auto joined = [&](const nlohmann::json& follower_meta) {
    const robossis::testing::ScratchDir dir("robossis_split_session");
    std::filesystem::create_directories(dir.path());
    WriteSplitLogs(dir.path(), leader_meta, follower_meta, over_dds, follower);
    return ReplaySplitSession(dir.path() / "leader.rlog", dir.path() / "follower.rlog").summary;
  };
  const nlohmann::json follower_meta = {{"rate_hz", 1000}, {"follower_rate_hz", 10000}};
  nlohmann::json right = follower_meta, off_by_1ms = follower_meta;
  right["status_stamp_offset_ns"] = kSystemOffsetNs;
  off_by_1ms["status_stamp_offset_ns"] = kSystemOffsetNs - 1'000'000;
  const auto s = joined(right);
  EXPECT_EQ(ForceError(s), expected);
  EXPECT_EQ(s.at("leader_ticks"), leader.size());
  EXPECT_EQ(s.at("follower_ticks"), follower.size());
  EXPECT_GT(std::abs(ForceError(joined(off_by_1ms)) - expected), 0.01);
  EXPECT_TRUE(joined(follower_meta).at("feedback_force_error_n_rms").is_null());
}

TEST(SplitSessionTest, RefusesLogsOfTheWrongUnitsNamingTheFile) {
  const robossis::testing::ScratchDir dir("robossis_split_session_units");
  std::filesystem::create_directories(dir.path());
  const nlohmann::json meta = {{"rate_hz", 1000}, {"follower_rate_hz", 10000}};
  WriteSplitLogs(dir.path(), meta, meta, {}, {});
  try {
    ReplaySplitSession(dir.path() / "follower.rlog", dir.path() / "leader.rlog");
    FAIL() << "a follower's log taken for a leader's";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("follower.rlog"), std::string::npos) << e.what();
  }
}

// A real run: the Bullet follower under the 517 N load, the load shown behind 100 ms, in one process. Its log split
// into the leader's and the follower's as two processes write them (the leader's status stamps moved onto a
// system clock, the follower's log holding that offset) and joined: the whole summary, the shown load against the
// true one included, is the one-process run's.
TEST(SplitSessionTest, AOneProcessRunSplitIntoTwoLogsGivesTheSameSummary) {
  const robossis::testing::ScratchDir dir("robossis_split_session_run");
  std::filesystem::create_directories(dir.path());
  TeleopSetup setup = TeleopSetup::Load(DefaultDataDir(), testing::Rsr(), testing::Sigma7());
  setup.transfer.caps.max_linear_speed_m_s = 0.1;
  setup.transfer.caps.max_angular_speed_rad_s = DegToRad(20);
  setup.follower.setpoint.caps = setup.transfer.caps;
  TeleopRequest request;
  request.device = "sim";
  request.follower = "sim";
  request.duration_s = 2;
  request.sim_load_n = 517;
  request.sim_load_nm = 74;
  request.link_delay_s = 0.1;
  request.feedback = "bilateral";
  const TeleopOutputs run = RunTeleop(request, setup, dir.path() / "session.rlog");
  ASSERT_TRUE(run.summary.at("feedback_force_error_n_rms").is_number());

  const SessionLog log = ReadSessionLog(dir.path() / "session.rlog");
  ASSERT_EQ(log.meta.at("status_stamp_offset_ns"), 0);  // the in-process link stamps on the follower's clock
  std::vector<LeaderTickRecord> leader = log.Decode<LeaderTickRecord>("leader", LeaderStreamSpec());
  for (auto& l : leader) l.follower_stamp_ns += kSystemOffsetNs;
  nlohmann::json follower_meta = log.meta;
  follower_meta["status_stamp_offset_ns"] = kSystemOffsetNs;
  nlohmann::json leader_meta = log.meta;
  leader_meta.erase("status_stamp_offset_ns");
  WriteSplitLogs(dir.path(), leader_meta, follower_meta, leader,
                 log.Decode<FollowerTickRecord>("follower", FollowerStreamSpec()),
                 log.Decode<SessionEndRecord>("end", EndStreamSpec()));
  const TeleopOutputs split = ReplaySplitSession(dir.path() / "leader.rlog", dir.path() / "follower.rlog");
  EXPECT_EQ(ForceError(split.summary), ForceError(run.summary));
  EXPECT_EQ(split.summary, run.summary);
  EXPECT_EQ(split.leader_csv, run.leader_csv);
  EXPECT_EQ(split.follower_csv, run.follower_csv);
}

}  // namespace
}  // namespace robossis::teleop
