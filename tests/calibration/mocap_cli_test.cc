// `robossis mocap inspect` and `robossis track-eval` as a user meets them.

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/robossis_cli.h"

namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

using robossis::testing::CommandRun;
using robossis::testing::Robossis;

std::string Data(const std::string& name) { return std::string(ROBOSSIS_MOCAP_TEST_DATA) + "/" + name; }

fs::path TempDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("robossis_mocap_cli_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(MocapCliTest, InspectJsonOnRealExport) {
  const CommandRun run = Robossis("mocap inspect " + Data("timeanddoctor_parse_optitrack_csv_test.csv") + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto j = nlohmann::json::parse(run.output);
  EXPECT_EQ(j["format_version"], "1.23");
  EXPECT_EQ(j["export_rate_hz"], 120.0);
  EXPECT_EQ(j["frames"], 499);
  EXPECT_EQ(j["length_units"], "Meters");
  EXPECT_EQ(j["rotation_type"], "Quaternion");
  ASSERT_EQ(j["rigid_bodies"].size(), 1u);
  EXPECT_EQ(j["rigid_bodies"][0]["name"], "ernesto_body");
  EXPECT_EQ(j["rigid_bodies"][0]["frames_present"], 498);
  EXPECT_EQ(j["rigid_bodies"][0]["gaps"], 1);
  EXPECT_EQ(j["rigid_bodies"][0]["longest_gap_frames"], 1);
  EXPECT_EQ(j["markers"], 4);
}

// Public exports are often the first frames of a take with the header's count left as it was: read them, say so on
// one line, and mark the summary. A row cut mid-line stays an error naming the line.
TEST(MocapCliTest, InspectReadsAnExcerptAndSaysSo) {
  const fs::path dir = TempDir("excerpt");
  std::ifstream in(Data("timeanddoctor_parse_optitrack_csv_test.csv"), std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t row = text.find("\n300,");
  std::ofstream(dir / "excerpt.csv", std::ios::binary) << text.substr(0, row + 1);
  std::ofstream(dir / "cut.csv", std::ios::binary) << text.substr(0, row + 30);
  const CommandRun json = Robossis("mocap inspect " + (dir / "excerpt.csv").string() + " --json");
  ASSERT_EQ(json.exit_code, 0) << json.output;
  const auto j = nlohmann::json::parse(json.output);
  EXPECT_EQ(j["frames"], 300);
  EXPECT_EQ(j["complete"], false);
  EXPECT_EQ(j["frames_in_header"], 499);
  const CommandRun plain = Robossis("mocap inspect " + (dir / "excerpt.csv").string());
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  EXPECT_THAT(plain.output, HasSubstr("excerpt: 300 frames read of the header's 499"));
  const CommandRun cut = Robossis("mocap inspect " + (dir / "cut.csv").string());
  EXPECT_NE(cut.exit_code, 0);
  EXPECT_THAT(cut.output, HasSubstr("line 308: the last row has"));
  fs::remove_all(dir);
}

TEST(MocapCliTest, InspectRejectsAssetlessTakeWithOneLine) {
  const CommandRun run = Robossis("mocap inspect " + Data("ha5dzs_optitrack-motive-file-converter_test_default.csv"));
  EXPECT_NE(run.exit_code, 0);
  EXPECT_THAT(run.output, HasSubstr("no assets"));
  EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1);
}

TEST(MocapCliTest, SimulateThenTrackEvalWritesSummary) {
  const fs::path dir = TempDir("eval");
  {
    std::ofstream cmd(dir / "commanded.csv");
    cmd << "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n";
    for (int k = 0; k <= 1500; ++k) {
      const double t = k * 0.01, e = 0.5 * (1 - std::cos(2 * M_PI * t / 15.0));
      cmd << t << "," << e * 20 * std::sin(0.7 * t) << "," << e * 15 * std::sin(1.1 * t + 1) << ","
          << 284 + e * 8 * std::sin(0.9 * t) << "," << e * 5 * std::sin(1.3 * t) << "," << e * 4 * std::sin(0.8 * t + 2)
          << "," << e * 9 * std::sin(0.6 * t + 0.5) << "\n";
    }
  }
  const CommandRun sim = Robossis("mocap simulate --reference " + (dir / "commanded.csv").string() + " --out " +
                                  (dir / "take.csv").string() + " --offset-s 1.25 --gaps 2 --units mm");
  ASSERT_EQ(sim.exit_code, 0) << sim.output;
  const CommandRun run = Robossis("track-eval --mocap " + (dir / "take.csv").string() +
                                  " --rigid-body MovingRing --reference " + (dir / "commanded.csv").string() +
                                  " --out " + (dir / "out").string() + " --json --no-plot");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto j = nlohmann::json::parse(run.output);
  EXPECT_NEAR(j["time_offset_s"].get<double>(), 1.25, 1e-3);
  EXPECT_LT(j["translation_error_mm"]["mean"].get<double>(), 0.1);  // tracker noise only
  EXPECT_TRUE(fs::exists(dir / "out" / "summary.json"));
  EXPECT_TRUE(fs::exists(dir / "out" / "errors.csv"));
  EXPECT_TRUE(fs::exists(dir / "out" / "tracked.tum"));
  fs::remove_all(dir);
}

TEST(MocapCliTest, TrackEvalBadInputsLeaveNoOutput) {
  const fs::path dir = TempDir("bad");
  { std::ofstream(dir / "cmd.tum") << "0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n"; }
  { std::ofstream(dir / "garbage.csv") << "not,a,motive,file\n"; }
  { std::ofstream(dir / "legacy.csv") << "Format Version,1.1\n"; }
  const std::string real = Data("timeanddoctor_parse_optitrack_csv_test.csv");
  {
    std::ifstream in(real, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(dir / "truncated.csv", std::ios::binary) << text.substr(0, text.find("\n300,") + 100);
  }
  struct Case {
    std::string args, expected;
  };
  const Case cases[] = {
      {"--mocap " + real + " --rigid-body Ring", "no rigid body named 'Ring'"},
      {"--mocap " + (dir / "garbage.csv").string() + " --rigid-body A", "expected 'Format Version"},
      {"--mocap " + (dir / "legacy.csv").string() + " --rigid-body A", "legacy format 1.1"},
      {"--mocap " + Data("ha5dzs_optitrack-motive-file-converter_test_default.csv") + " --rigid-body A", "no assets"},
      {"--mocap " + (dir / "missing.csv").string() + " --rigid-body A", "cannot open"},
      {"--mocap " + (dir / "truncated.csv").string() + " --rigid-body ernesto_body", "truncated"},
  };
  for (const Case& c : cases) {
    const CommandRun run =
        Robossis("track-eval " + c.args + " --reference " + (dir / "cmd.tum").string() + " --out " + (dir / "out").string());
    EXPECT_NE(run.exit_code, 0) << c.args;
    EXPECT_THAT(run.output, HasSubstr(c.expected)) << c.args;
    EXPECT_FALSE(fs::exists(dir / "out")) << c.args;
  }
  fs::remove_all(dir);
}

}  // namespace
