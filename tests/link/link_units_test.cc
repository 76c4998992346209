// `robossis leader` and `robossis follower` as two processes over the DDS link on loopback, as a user runs them:
// `robossis teleop --link dds` into the Bullet follower with security on, and `kill -9` of either process followed
// by a restart while the other runs. Each test uses its own DDS domain and credentials (link_test_support) and
// always stops the processes it starts (ChildProcess kills and reaps on scope exit). No timing assertions: the
// waits only give the processes time to reach the state under test.

#include <csignal>
#include <iostream>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "src/core/child_process.h"
#include "src/core/config.h"
#include "src/core/files.h"
#include "src/link/dds_leader_link.h"
#include "src/link/keys.h"
#include "tests/link/link_test_support.h"
#include "tests/support/robossis_cli.h"
#include "tests/support/scratch_dir.h"

namespace robossis::link {
namespace {

using namespace std::chrono_literals;

// The caps of the demo's fast-hand run (the shipped 10 mm/s would never reach the walls in a short test).
constexpr double kCapMmS = 100, kCapDegS = 20;

// `keys` is the folder of `keys init` (teleop --link dds) or a unit's own folder of it (leader, follower).
std::vector<std::string> Common(const std::filesystem::path& keys) {
  return {"--keys",           keys.string(),               "--domain", std::to_string(testing::TestDomain()),
          "--max-speed-mm-s", std::to_string(kCapMmS),     "--max-angular-speed-deg-s", std::to_string(kCapDegS),
          "--no-plots"};
}

std::string FastHand() { return "replay:" + (DefaultDataDir() / "teleop" / "fast_hand.csv").string(); }

std::vector<std::string> Args(std::vector<std::string> unit, const std::filesystem::path& out, double duration_s,
                              const std::filesystem::path& keys_init_dir = testing::TestKeys()) {
  const auto common = Common(keys_init_dir / unit.front());
  unit.insert(unit.end(), common.begin(), common.end());
  unit.insert(unit.end(), {"--out", out.string(), "--duration-s", std::to_string(duration_s)});
  return unit;
}

ChildProcess Follower(const std::filesystem::path& dir, const std::string& name) {
  return ChildProcess(ROBOSSIS_BINARY, Args({"follower", "--follower", "recorder"}, dir / name, 600),
                      dir / (name + ".log"));
}

ChildProcess Leader(const std::filesystem::path& dir, const std::string& name, double duration_s) {
  return ChildProcess(ROBOSSIS_BINARY,
                      Args({"leader", "--device", FastHand(), "--method", "proxy-safe"}, dir / name, duration_s),
                      dir / (name + ".log"));
}

nlohmann::json Summary(const std::filesystem::path& dir) { return nlohmann::json::parse(ReadTextFile(dir / "summary.json")); }

void ExpectExitZero(ChildProcess& p, const std::filesystem::path& log, std::chrono::seconds timeout = 120s) {
  const auto e = p.WaitFor(timeout);
  ASSERT_TRUE(e.has_value()) << "still running; log: " << ReadTextFile(log);
  EXPECT_TRUE(e->exited && e->code == 0) << e->Describe() << "; log: " << ReadTextFile(log);
}

void StopFollower(ChildProcess& follower, const std::filesystem::path& log) {
  follower.Signal(SIGINT);
  ExpectExitZero(follower, log, 30s);
}

// No limit crossed, and measured speeds near the caps: a jump on recovery (a pose millimetres away within one tick)
// would read as thousands of mm/s. 1.5x: the Bullet follower's measured speed overshoots the commanded one by ~10 %
// over the summary's 10 ms window.
void ExpectNoJump(const nlohmann::json& follower) {
  EXPECT_EQ(follower["follower_limit_violations"], 0);
  EXPECT_LE(follower["max_follower_speed_mm_s"].get<double>(), 1.5 * kCapMmS);
  EXPECT_LE(follower["max_follower_angular_speed_deg_s"].get<double>(), 1.5 * kCapDegS);
}

// The figures RELIABILITY.md's table reports, on one line of the test's output.
void PrintFigures(const std::string& test_case, const nlohmann::json& follower) {
  std::cout << "figures: " << test_case << ": set-points accepted " << follower["setpoints_accepted"]
            << ", rejected " << follower["setpoints_rejected"] << " " << follower["setpoints_rejected_by_reason"].dump()
            << ", limit violations "
            << follower["follower_limit_violations"] << ", watchdog holds " << follower["watchdog_holds"]
            << ", max speed " << follower["max_follower_speed_mm_s"] << " mm/s "
            << follower["max_follower_angular_speed_deg_s"] << " deg/s, transitions "
            << follower["follower_transitions"].dump() << "\n";
}

bool HasTransition(const nlohmann::json& s, const std::string& to, const std::string& reason = "") {
  for (const auto& t : s["follower_transitions"]) {
    if (t["to"] == to && (reason.empty() || t["reason"] == reason)) return true;
  }
  return false;
}

// Under AddressSanitizer the Bullet follower's 10 kHz tick misses 17-26% of its deadlines even on an idle machine,
// and the two units' SCHED_FIFO loops then leave the link's receive path too little CPU for the 1 kHz stream: most
// set-points reach the follower later than the 30 ms freshness bound and are dropped as stale, and the follower
// holds, as designed (RELIABILITY.md, "Sanitizers in CI"). The sanitized build therefore drives the recorder back end
// here; the Bullet follower's own code runs sanitized in the in-process tests.
#if defined(__SANITIZE_ADDRESS__)
constexpr const char* kTwoProcessFollower = "recorder";
#else
constexpr const char* kTwoProcessFollower = "sim";
#endif

TEST(LinkUnitsTest, TeleopOverSecuredDdsDrivesTheBulletFollowerFromTwoProcesses) {
  robossis::testing::ScratchDir dir("robossis_link_units_teleop");
  const bool bullet = std::string(kTwoProcessFollower) == "sim";
  std::string args = std::string("teleop --link dds --follower ") + kTwoProcessFollower + " --device " + FastHand() +
                     " --method proxy-safe --json --duration-s 5 --out " + (dir.path() / "run").string();
  // The follower's load shown at the hand: the muscles are the Bullet follower's only.
  if (bullet) args += " --feedback bilateral --sim-load-n 300";
  for (const std::string& a : Common(testing::TestKeys())) args += " " + a;
  const auto run = robossis::testing::Robossis(args, false);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto s = nlohmann::json::parse(run.output);
  EXPECT_EQ(s["link"], "dds");
  EXPECT_EQ(s["secure"], true);
  const auto& leader = s["leader"];
  const auto& follower = s["follower"];
  // --duration-s bounds the leader's whole run: its wait for the follower, then its loop for the rest.
  EXPECT_NEAR(leader["follower_wait_s"].get<double>() + leader["loop_duration_s"].get<double>(), 5.0, 1e-9);
  // The loop at 1 kHz: every period either ticked or was counted as missed (a loaded machine, or the sanitized
  // build, makes the loop skip deadlines, never lose them).
  EXPECT_GE(leader["leader_ticks"].get<double>() + leader["leader_overruns"].get<double>(),
            0.98e3 * leader["loop_duration_s"].get<double>())
      << "ticks " << leader["leader_ticks"] << ", overruns " << leader["leader_overruns"];
  EXPECT_EQ(leader["follower_ticks"], 0);             // each process records its own unit only
  EXPECT_EQ(follower["leader_ticks"], 0);
  // Over 5 s at 1 kHz, the secured discovery and handshake first; on a loaded machine the link's send thread wakes
  // late and skips to the newest set-point.
  EXPECT_GT(follower["setpoints_accepted"].get<int>(), 500);
  PrintFigures("teleop --link dds", follower);
  EXPECT_EQ(follower["link"]["rejected_invalid"], 0);
  EXPECT_TRUE(HasTransition(follower, "enabled"));
  ExpectNoJump(follower);
  EXPECT_EQ(leader["nonfinite_outputs"], 0);
  // The load shown (the leader's log) against the follower's true load (the follower's log), joined on the
  // follower's clock: judged over DDS as in one process.
  if (bullet) {
    EXPECT_TRUE(s["feedback_force_error_n_rms"].is_number()) << s["feedback_force_error_n_rms"];
    EXPECT_GT(leader["max_feedback_force_n"].get<double>(), 0.0);
    std::cout << "figures: teleop --link dds --feedback bilateral --sim-load-n 300: feedback_force_error_n_rms "
              << s["feedback_force_error_n_rms"] << ", max_feedback_force_n " << leader["max_feedback_force_n"] << "\n";
  }
  for (const char* f : {"summary.json", "leader/summary.json", "leader/leader.csv", "leader/session.rlog",
                        "follower/summary.json", "follower/follower.csv", "follower/session.rlog"}) {
    EXPECT_TRUE(std::filesystem::exists(dir.path() / "run" / f)) << f;
  }
  // Each half's log replays into its own summary (the link's counters are the process's, not in the log, as is the
  // leader's wait for the follower before its log began).
  for (const char* unit : {"leader", "follower"}) {
    const auto replay = robossis::testing::Robossis(
        "replay " + (dir.path() / "run" / unit / "session.rlog").string() + " --no-plots --json --out " +
            (dir.path() / (std::string("replay_") + unit)).string(),
        false);
    ASSERT_EQ(replay.exit_code, 0) << replay.output;
    nlohmann::json live = s[unit];
    for (const char* key : {"link", "follower_wait_s", "loop_duration_s"}) live.erase(key);
    EXPECT_EQ(nlohmann::json::parse(replay.output), live) << unit;
  }
}

TEST(LinkUnitsTest, LeaderKilledThenRestartedWhileTheFollowerRuns) {
  robossis::testing::ScratchDir dir("robossis_link_units_leader_kill");
  std::filesystem::create_directories(dir.path());
  ChildProcess follower = Follower(dir.path(), "follower");
  {
    ChildProcess first = Leader(dir.path(), "leader1", 60);
    std::this_thread::sleep_for(6s);  // discovery, the follower heard, then a few seconds of teleoperation
    ASSERT_TRUE(first.running()) << ReadTextFile(dir.path() / "leader1.log");
    first.Signal(SIGKILL);
    EXPECT_EQ(first.Wait().signal, SIGKILL);
    // What the killed leader recorded survives: its log (in the folder it was staging) replays, cut short.
    const std::filesystem::path staged =
        dir.path() / ("leader1.partial-" + std::to_string(first.pid())) / "session.rlog";
    ASSERT_TRUE(std::filesystem::exists(staged));
    const auto replay = robossis::testing::Robossis(
        "replay " + staged.string() + " --no-plots --json --out " + (dir.path() / "leader1_replay").string(), false);
    ASSERT_EQ(replay.exit_code, 0) << replay.output;
    const auto killed = nlohmann::json::parse(replay.output);
    EXPECT_FALSE(killed["complete"].get<bool>());
    EXPECT_GT(killed["leader_ticks"].get<int>(), 500);
  }
  std::this_thread::sleep_for(1s);  // the follower holds, then disables itself (leader lost)
  ChildProcess second = Leader(dir.path(), "leader2", 6);
  {
    // The operator enables it again from the panel: the restarted leader may not (its credentials grant no
    // state_command), it only streams set-points.
    DdsLeaderLink panel(testing::LoopbackOptions(Role::kPanel));
    teleop::FollowerStatusMessage status;
    ASSERT_TRUE(testing::WaitFor(
        [&] { return panel.TakeFollowerStatus(status) && status.state == teleop::OperatingState::kDisabled; }, 60s));
    // Sent again every 100 ms (numbered on): one sent before the panel's writer has matched is not delivered.
    teleop::StateCommandMessage enable;
    enable.session = 1;
    enable.command = teleop::StateCommand::kEnable;
    enable.source = teleop::kFromPanel;
    EXPECT_TRUE(testing::WaitFor(
        [&] {
          ++enable.sequence;
          enable.stamp_ns = static_cast<std::int64_t>(enable.sequence) * 100'000'000;
          panel.SendCommand(enable);
          std::this_thread::sleep_for(100ms);
          return panel.TakeFollowerStatus(status) && status.state != teleop::OperatingState::kDisabled;
        },
        60s));
  }
  ExpectExitZero(second, dir.path() / "leader2.log");
  StopFollower(follower, dir.path() / "follower.log");

  const auto f = Summary(dir.path() / "follower");
  EXPECT_TRUE(HasTransition(f, "disabled", "leader_lost")) << f["follower_transitions"].dump();
  // The panel enabled it again and it followed the new leader.
  int enabled = 0;
  for (const auto& t : f["follower_transitions"]) enabled += t["to"] == "enabled";
  EXPECT_GE(enabled, 2) << f["follower_transitions"].dump();
  EXPECT_GE(f["watchdog_holds"].get<int>(), 1);
  ExpectNoJump(f);
  EXPECT_EQ(f["complete"], true);
  EXPECT_EQ(Summary(dir.path() / "leader2")["nonfinite_outputs"], 0);
  PrintFigures("kill -9 leader, restart", f);
}

TEST(LinkUnitsTest, FollowerKilledThenRestartedWhileTheLeaderRuns) {
  robossis::testing::ScratchDir dir("robossis_link_units_follower_kill");
  std::filesystem::create_directories(dir.path());
  ChildProcess leader = Leader(dir.path(), "leader", 10);
  {
    ChildProcess first = Follower(dir.path(), "follower1");
    std::this_thread::sleep_for(5s);
    ASSERT_TRUE(first.running()) << ReadTextFile(dir.path() / "follower1.log");
    first.Signal(SIGKILL);
    EXPECT_EQ(first.Wait().signal, SIGKILL);
    const std::filesystem::path staged =
        dir.path() / ("follower1.partial-" + std::to_string(first.pid())) / "session.rlog";
    const auto replay = robossis::testing::Robossis(
        "replay " + staged.string() + " --no-plots --json --out " + (dir.path() / "follower1_replay").string(), false);
    ASSERT_EQ(replay.exit_code, 0) << replay.output;
    const auto killed = nlohmann::json::parse(replay.output);
    EXPECT_GT(killed["setpoints_accepted"].get<int>() + killed["follower_ticks"].get<int>(), 0);
    EXPECT_EQ(killed["follower_limit_violations"], 0);
  }
  ChildProcess second = Follower(dir.path(), "follower2");
  ExpectExitZero(leader, dir.path() / "leader.log");
  StopFollower(second, dir.path() / "follower2.log");

  const auto f = Summary(dir.path() / "follower2");
  EXPECT_TRUE(HasTransition(f, "enabled")) << f["follower_transitions"].dump();
  EXPECT_GT(f["setpoints_accepted"].get<int>(), 0);
  ExpectNoJump(f);
  const auto l = Summary(dir.path() / "leader");
  EXPECT_EQ(l["nonfinite_outputs"], 0);
  EXPECT_EQ(l["complete"], true);
  PrintFigures("kill -9 follower, restart", f);
}

// A leader holding credentials from another CA (a second `keys init`) exits, naming the refused handshake, instead of
// waiting for ever; the right leader started next is accepted. The time it took is printed, not asserted.
TEST(LinkUnitsTest, ALeaderThatCannotAuthenticateExitsWithTheCauseAndTheRightOneIsAcceptedNext) {
  robossis::testing::ScratchDir dir("robossis_link_units_rogue");
  std::filesystem::create_directories(dir.path());
  const std::filesystem::path rogue_keys = dir.path() / "rogue-keys";
  InitKeys(rogue_keys, KeysInitOptions{});
  ChildProcess follower = Follower(dir.path(), "follower");
  {
    ChildProcess rogue(ROBOSSIS_BINARY,
                       Args({"leader", "--device", FastHand(), "--method", "proxy-safe"}, dir.path() / "rogue", 30,
                            rogue_keys),
                       dir.path() / "rogue.log");
    const auto e = rogue.WaitFor(120s);
    ASSERT_TRUE(e.has_value()) << "the rogue leader still runs: " << ReadTextFile(dir.path() / "rogue.log");
    EXPECT_TRUE(e->exited && e->code != 0) << e->Describe();
    const std::string log = ReadTextFile(dir.path() / "rogue.log");
    EXPECT_NE(log.find("no follower authenticated"), std::string::npos) << log;
    EXPECT_NE(log.find("handshake was refused"), std::string::npos) << log;
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "rogue" / "summary.json"));
  }
  const auto start = std::chrono::steady_clock::now();
  ChildProcess leader = Leader(dir.path(), "leader", 2);
  const char* accepted = "follower authenticated and heard after ";
  const bool heard = testing::WaitFor(
      [&] {
        std::this_thread::sleep_for(10ms);
        return ReadTextFile(dir.path() / "leader.log").find(accepted) != std::string::npos;
      },
      120s);
  const double since_start_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ExpectExitZero(leader, dir.path() / "leader.log");
  StopFollower(follower, dir.path() / "follower.log");
  const std::string log = ReadTextFile(dir.path() / "leader.log");
  ASSERT_TRUE(heard) << log;
  const auto at = log.find(accepted);
  std::cout << "figures: the right leader after the rogue: accepted " << since_start_s
            << " s after its process started (" << log.substr(at, log.find('\n', at) - at) << ")\n";
  EXPECT_GT(Summary(dir.path() / "follower")["setpoints_accepted"].get<int>(), 0);
}

}  // namespace
}  // namespace robossis::link
