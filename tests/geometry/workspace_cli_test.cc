// `robossis workspace ...` as a user meets it.

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/robossis_cli.h"

namespace {

namespace fs = std::filesystem;

using robossis::testing::CommandRun;
using robossis::testing::Robossis;

class WorkspaceCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("robossis_ws_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Dir(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

nlohmann::json ReadJson(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

TEST_F(WorkspaceCliTest, DexterousWritesMeshesAndSummary) {
  const CommandRun run = Robossis("workspace dexterous --rpy-deg 0,5,0 --resolution-mm 10 --out " + Dir("dex"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json s = ReadJson(Dir("dex") + "/summary.json");
  for (const char* key : {"volume", "extents", "triangles", "watertight"}) EXPECT_TRUE(s.contains(key)) << key;
  EXPECT_TRUE(s["watertight"].get<bool>());
  EXPECT_GT(s["volume"].get<double>(), 1e5);  // mm^3
  EXPECT_TRUE(fs::file_size(Dir("dex") + "/mesh.stl") == 84 + 50 * s["triangles"].get<std::size_t>());
  EXPECT_TRUE(fs::exists(Dir("dex") + "/mesh.ply"));
}

TEST_F(WorkspaceCliTest, RotationalAndHcWriteSummaries) {
  ASSERT_EQ(Robossis("workspace rotational --position-mm 0,0,284 --resolution-deg 4 --out " + Dir("rot")).exit_code, 0);
  EXPECT_TRUE(ReadJson(Dir("rot") + "/summary.json")["watertight"].get<bool>());
  ASSERT_EQ(Robossis("workspace hc --resolution-mm 10 --resolution-deg 10 --out " + Dir("hc")).exit_code, 0);
  const nlohmann::json s = ReadJson(Dir("hc") + "/summary.json");
  EXPECT_TRUE(s["slices"]["wrist"]["watertight"].get<bool>());
  EXPECT_TRUE(s["watertight"].get<bool>());
}

TEST_F(WorkspaceCliTest, BadResolutionIsAOneLineErrorAndWritesNothing) {
  for (const std::string bad : {"0", "-2", "abc"}) {
    const CommandRun run = Robossis("workspace dexterous --resolution-mm " + bad + " --out " + Dir("bad"));
    EXPECT_NE(run.exit_code, 0);
    EXPECT_NE(run.output.find("resolution"), std::string::npos) << run.output;
    EXPECT_FALSE(fs::exists(Dir("bad")));
  }
}

TEST_F(WorkspaceCliTest, UnreachableOrientationIsAClearError) {
  const CommandRun run = Robossis("workspace dexterous --rpy-deg 80,0,0 --resolution-mm 10 --out " + Dir("x"));
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.output.find("empty"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(Dir("x")));
}

TEST_F(WorkspaceCliTest, AtlasThenQueryJson) {
  ASSERT_EQ(Robossis("workspace atlas --coarse --error-samples 0 --out " + Dir("atlas")).exit_code, 0);
  const CommandRun run = Robossis("workspace query --atlas " + Dir("atlas") + " --pose 0,0,284,0,0,0 --json", false);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json q = nlohmann::json::parse(run.output);
  EXPECT_GT(q["signed_distance_mm"].get<double>(), 0);
  EXPECT_GT(q["signed_angle_deg"].get<double>(), 0);
  EXPECT_EQ(q["normal"].size(), 3u);
  EXPECT_EQ(q["nearest_mm"].size(), 3u);
  // Far outside: negative.
  const nlohmann::json out = nlohmann::json::parse(
      Robossis("workspace query --atlas " + Dir("atlas") + " --pose 0,0,500,0,0,0 --json", false).output);
  EXPECT_LT(out["signed_distance_mm"].get<double>(), -100);
}

TEST_F(WorkspaceCliTest, LiveQueryUsesSlicesMadeAtThePose) {
  // Off the coarse atlas' nodes (yaw 9 deg): --live answers from slices made at this pose, and needs no atlas.
  const CommandRun run = Robossis("workspace query --live --pose 20,0,284,0,0,9 --json", false);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json q = nlohmann::json::parse(run.output);
  EXPECT_TRUE(q["live"]["translation"].get<bool>());
  EXPECT_TRUE(q["live"]["rotation"].get<bool>());
  EXPECT_NEAR(q["dexterous_slice_rpy_deg"][2].get<double>(), 9.0, 1e-9);
  EXPECT_NEAR(q["rotational_slice_position_mm"][0].get<double>(), 20.0, 1e-9);
  EXPECT_GT(q["signed_distance_mm"].get<double>(), 0);
  // Without --atlas and without --live: a one-line error naming the option.
  const CommandRun bad = Robossis("workspace query --pose 20,0,284,0,0,9 --json");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("--atlas"), std::string::npos) << bad.output;
}

TEST_F(WorkspaceCliTest, QueryOfACorruptAtlasFails) {
  fs::create_directories(Dir("notatlas"));
  const CommandRun run = Robossis("workspace query --atlas " + Dir("notatlas") + " --pose 0,0,284,0,0,0 --json");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.output.find("manifest.json"), std::string::npos) << run.output;
}

}  // namespace
