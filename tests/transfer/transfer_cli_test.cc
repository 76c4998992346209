// `robossis transfer` and `robossis move` as a user meets them: outputs, summary keys, one-line errors.

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/robossis_cli.h"

namespace {

using ::testing::HasSubstr;

using robossis::testing::CommandRun;
using robossis::testing::Robossis;

std::filesystem::path Temp(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("robossis_transfer_cli_" + name);
}

// 0.6 s of a hand at 20 mm/s along x.
std::filesystem::path SmallHcFile() {
  const auto p = Temp("hand.csv");
  std::ofstream out(p);
  out << "time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n";
  for (int k = 0; k <= 600; ++k) out << k * 1e-3 << "," << 20.0 * k * 1e-3 << ",0,0,0,0,0\n";
  return p;
}

TEST(TransferCliTest, TransferWritesTheSummaryKeysAndFiles) {
  const auto out = Temp("out");
  std::filesystem::remove_all(out);
  const CommandRun run =
      Robossis("transfer --hc " + SmallHcFile().string() + " --out " + out.string() + " --no-plots --json");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto doc = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  for (const char* key : {"max_speed_mm_s", "max_angular_speed_deg_s", "max_accel_mm_s2", "max_jerk_mm_s3",
                          "delay_ms", "steps_error_max"}) {
    EXPECT_TRUE(doc.contains(key)) << key;
  }
  EXPECT_LE(doc["max_speed_mm_s"].get<double>(), 10.0);  // [paper] cap 10 mm/s; the hand moves at 20
  EXPECT_GT(doc["max_speed_mm_s"].get<double>(), 9.0);
  EXPECT_LE(doc["steps_error_max"].get<double>(), 0.5);
  for (const char* f : {"setpoints.csv", "joints.csv", "pulses.csv", "hc.csv", "transfer_1khz.csv"}) {
    EXPECT_TRUE(std::filesystem::exists(out / f)) << f;
  }
}

TEST(TransferCliTest, MoveEndsExactlyAndReportsSteps) {
  const auto out = Temp("move");
  std::filesystem::remove_all(out);
  const CommandRun run = Robossis("move --delta-mm 0,0,2 --duration-s 0.5 --out " + out.string() + " --no-plots --json");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto doc = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  // eq. 9 peak speed: pi/2 · 2 mm / 0.5 s.
  EXPECT_NEAR(doc["max_speed_mm_s"].get<double>(), 3.14159265 / 2 * 2 / 0.5, 1e-3);
  EXPECT_LE(doc["steps_error_max"].get<double>(), 0.5);
}

class TransferCliBadInputTest : public ::testing::TestWithParam<std::pair<std::string, std::string>> {};

TEST_P(TransferCliBadInputTest, OneLineErrorAndNonZeroExit) {
  const auto out = Temp("bad");
  std::filesystem::remove_all(out);
  const CommandRun run = Robossis(GetParam().first + " --out " + out.string() + " --no-plots");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_THAT(run.output, HasSubstr(GetParam().second));
  EXPECT_FALSE(std::filesystem::exists(out));  // nothing half-written
}

INSTANTIATE_TEST_SUITE_P(
    Cases, TransferCliBadInputTest,
    ::testing::Values(std::make_pair("transfer --scenario nope", "unknown scenario 'nope'"),
                      std::make_pair("transfer --hc /nonexistent.csv", "cannot open"),
                      std::make_pair("transfer", "exactly one of --hc"),
                      std::make_pair("move --delta-mm 1,2 --duration-s 1", "--delta-mm: expected 3"),
                      std::make_pair("move --delta-mm 0,0,5 --duration-s -1", "--duration-s"),
                      std::make_pair("move --delta-mm 0,0,500 --duration-s 1", "leaves the RSR's workspace"),
                      std::make_pair("transfer --scenario slow --max-speed-mm-s -3", "--max-speed-mm-s"),
                      // One validated path: a duration that breaks the caps is refused, clinical or not.
                      std::make_pair("move --delta-deg 0,0,2 --duration-s 0.255 --clinical", "breaks the speed caps"),
                      std::make_pair("move --delta-deg 0,0,2 --duration-s 0.255", "breaks the speed caps"),
                      std::make_pair("move --delta-mm 0,0,2 --speed-mm-s 50", "breaks the speed caps"),
                      // 0 is a value, never "the default".
                      std::make_pair("move --delta-mm 0,0,5 --duration-s 1 --max-speed-mm-s 0",
                                     "--max-speed-mm-s: expected a speed cap in (0, 1000] mm/s, got 0 mm/s"),
                      std::make_pair("move --delta-mm 0,0,5 --duration-s 0", "--duration-s: expected a finite duration in (0, 3600] s"),
                      std::make_pair("move --delta-mm 0,0,5 --duration-s 1 --clinical --max-speed-mm-s 50",
                                     "excludes"),
                      std::make_pair("move --delta-mm 0,0,5 --duration-s 1e9", "at most 3600 s")));

// A hand that turns (7.2 deg/s under an 8 deg/s cap) to 40 deg of yaw: the follower stops at the spherical cones
// (25 deg) without crossing them, and the run says so.
TEST(TransferCliTest, TransferStopsAtTheConesAndSaysSo) {
  const auto hand = Temp("yaw.csv");
  {
    std::ofstream f(hand);
    f << "time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n";
    for (int k = 0; k <= 6000; k += 2) f << k * 1e-3 << ",0,0,0,0,0," << std::min(7.2 * k * 1e-3, 40.0) << "\n";
  }
  const auto out = Temp("yaw");
  std::filesystem::remove_all(out);
  const CommandRun run = Robossis("transfer --hc " + hand.string() + " --max-angular-speed-deg-s 8 --out " +
                                  out.string() + " --no-plots");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("stopped at a joint limit"));
  EXPECT_THAT(run.output, HasSubstr("spherical_cone"));
  const auto doc = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  EXPECT_EQ(doc["follower_limit_violations"].get<int>(), 0);
  EXPECT_GT(doc["guard_limited_ticks"].get<int>(), 1000);
  EXPECT_GE(doc["min_limit_margin"].get<double>(), 0.0);
}

}  // namespace
