// `robossis teleop --clock simulated` and `robossis replay` as a user runs them: the files, the summary's keys,
// the replay reproducing the summary, a one-line error on bad input, and `robossis estop` with nobody to hear it.

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "src/core/config.h"
#include "tests/support/robossis_cli.h"

namespace robossis {
namespace {

using testing::Robossis;

std::filesystem::path Temp(const std::string& name) {
  const auto p = std::filesystem::temp_directory_path() / name;
  std::filesystem::remove_all(p);
  return p;
}

std::size_t Lines(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::size_t n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

TEST(TeleopCliTest, SimulatedSessionWritesItsFilesAndReplayReproducesTheSummary) {
  const auto out = Temp("robossis_teleop_cli");
  const std::string hand = (DefaultDataDir() / "teleop" / "fast_hand.csv").string();
  const auto run = Robossis("teleop --device replay:" + hand + " --method proxy-safe --follower sim --rate-hz 1000 "
                            "--duration-s 2 --clock simulated --no-plots --json --out " + out.string(), false);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto summary = nlohmann::json::parse(run.output);
  for (const char* key : {"leader_ticks", "follower_ticks", "leader_overruns", "follower_overruns",
                          "leader_period_jitter_us_p99", "follower_period_jitter_us_p99", "max_force_n",
                          "max_torque_nm", "nonfinite_outputs", "follower_limit_violations", "max_follower_speed_mm_s",
                          "max_follower_angular_speed_deg_s", "hand_to_setpoint_delay_ms",
                          "hand_to_setpoint_delay_status", "hand_to_setpoint_delay_judged_fraction", "watchdog_holds",
                          "follower_transitions"}) {
    EXPECT_TRUE(summary.contains(key)) << key;
  }
  EXPECT_EQ(summary["leader_ticks"], 2000);
  EXPECT_EQ(summary["follower_ticks"], 20000);
  // Every loop's overruns by cause, the simulated robot's own loop (1 kHz) included; none on the simulated clock.
  EXPECT_EQ(summary["plant_ticks"], 2000);
  for (const char* loop : {"leader", "follower", "plant"}) {
    for (const char* cause : {"_overruns_late_wake", "_overruns_long_tick"}) {
      EXPECT_EQ(summary[std::string(loop) + cause], 0) << loop << cause;
    }
  }
  EXPECT_EQ(summary["follower_limit_violations"], 0);
  // The fast hand at the shipped 10 mm/s cap: no single delay, and the summary says so rather than a number.
  EXPECT_TRUE(summary["hand_to_setpoint_delay_ms"].is_null());
  EXPECT_EQ(summary["hand_to_setpoint_delay_status"], "cap_binds");
  for (const char* f : {"summary.json", "leader.csv", "follower.csv", "loop_periods.csv", "session.rlog"}) {
    EXPECT_TRUE(std::filesystem::exists(out / f)) << f;
  }
  EXPECT_GE(Lines(out / "follower.csv"), 2 * 100 + 1u);  // >= 100 Hz over 2 s, plus the header

  const auto replayed = Temp("robossis_teleop_cli_replay");
  const auto replay = Robossis("replay " + (out / "session.rlog").string() + " --no-plots --json --out " +
                               replayed.string(), false);
  ASSERT_EQ(replay.exit_code, 0) << replay.output;
  EXPECT_EQ(nlohmann::json::parse(replay.output), summary);
  std::filesystem::remove_all(out);
  std::filesystem::remove_all(replayed);
}

TEST(TeleopCliTest, BadInputIsOneLineNamingTheOption) {
  const auto out = Temp("robossis_teleop_cli_bad");
  const auto run = Robossis("teleop --method nope --duration-s 1 --out " + out.string());
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find("robossis: error: --method"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  const auto dev = Robossis("teleop --device replay:/nonexistent.csv --duration-s 1 --out " + out.string());
  EXPECT_EQ(dev.exit_code, 1);
  EXPECT_NE(dev.output.find("robossis: error:"), std::string::npos) << dev.output;
}

// Bilateral feedback as a user asks for it: the muscles' load felt behind a delay, the summary's keys, and a bad
// --feedback, --feedback-passivity or a load on a follower without muscles refused in one line.
TEST(TeleopCliTest, BilateralFeedbackBehindADelayAndItsBadInput) {
  const auto out = Temp("robossis_teleop_cli_bilateral");
  const auto run = Robossis("teleop --device sim --follower sim --duration-s 1 --clock simulated --max-speed-mm-s 100 "
                            "--feedback bilateral --feedback-gain 0.02 --feedback-passivity classic --link-delay-ms 50 "
                            "--sim-load-n 517 --sim-load-nm 74 --no-plots --json --out " + out.string(), false);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto summary = nlohmann::json::parse(run.output);
  for (const char* key : {"feedback_energy_j", "max_feedback_force_n", "feedback_force_error_n_rms",
                          "position_drift_mm", "tdpa_active_fraction"}) {
    EXPECT_TRUE(summary.contains(key)) << key;
  }
  EXPECT_GT(summary["max_feedback_force_n"].get<double>(), 0.9 * 0.02 * 517);
  EXPECT_LE(summary["feedback_energy_max_j"].get<double>(), 1e-9);
  std::filesystem::remove_all(out);
  // Both halves of the network form and the let-go detector (the hand holds on: it never fires).
  const auto network = Robossis("teleop --device sim --follower sim --duration-s 1 --clock simulated "
                                "--max-speed-mm-s 100 --feedback bilateral --feedback-passivity network "
                                "--let-go-detector --link-delay-ms 50 --sim-load-n 517 --no-plots --json --out " +
                                    out.string(),
                                false);
  ASSERT_EQ(network.exit_code, 0) << network.output;
  const auto n = nlohmann::json::parse(network.output);
  EXPECT_LE(n["follower_port_excess_max_j"].get<double>(), 0.02);
  EXPECT_EQ(n["let_go_detected_s"].get<double>(), -1.0);
  std::filesystem::remove_all(out);
  for (const std::string bad : {"--feedback loud", "--feedback-passivity maybe", "--follower recorder --sim-load-n 5"}) {
    const auto r = Robossis("teleop --duration-s 1 " + bad + " --out " + out.string());
    EXPECT_EQ(r.exit_code, 1) << bad;
    EXPECT_NE(r.output.find("robossis: error: --"), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
}

TEST(TeleopCliTest, EStopWithoutAFollowerSaysSoAndFails) {
  // A domain of this process's own, loopback only, unsecured (the warning is printed): nobody answers.
  const std::string domain = std::to_string(1 + getpid() % 200);
  const auto run = Robossis("estop --insecure --interface 127.0.0.1 --peer 127.0.0.1 --domain " + domain +
                            " --timeout-s 0.3");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find("robossis: error: estop: no follower heard within --timeout-s"), std::string::npos)
      << run.output;
  const auto bad = Robossis("estop --insecure --timeout-s 0");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("--timeout-s"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace robossis
