// Hostile inputs of the geometry and robot commands: error-sample counts that never finish, degenerate robot
// geometry, atlas queries far off the grid, partial atlas manifests, wrenches that overflow the statics. Each runs
// the robossis binary as a user would.

#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/hostile_cli_test.h"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using robossis::testing::CommandRun;
using robossis::testing::Robossis;

class HostileGeometryTest : public robossis::testing::HostileCliTest {
 protected:
  // A copy of the data folder with `from` replaced by `to` in rsr.yaml.
  fs::path DataDirWithRsr(const std::string& from, const std::string& to) const {
    return DataDirWith("rsr.yaml", [&](const std::string& t) { return Replace(t, from, to); });
  }
  // A coarse atlas, built once per test, and a fresh copy of it to damage (a new folder per copy).
  fs::path Atlas() {
    const fs::path atlas = dir_ / "atlas";
    if (!fs::exists(atlas / "manifest.json")) {
      const CommandRun run = Robossis("workspace atlas --coarse --error-samples 0 --out " + Q(atlas));
      EXPECT_EQ(run.exit_code, 0) << run.output;
    }
    return atlas;
  }
  fs::path CopyOfAtlas() {
    const fs::path copy = dir_ / ("atlas" + std::to_string(copies_++));
    fs::copy(Atlas(), copy, fs::copy_options::recursive);
    return copy;
  }
  int copies_ = 0;
};

TEST_F(HostileGeometryTest, ErrorSampleCountsOutOfRangeAreRefusedBeforeWork) {
  for (const std::string cmd : {"workspace dexterous --resolution-mm 10", "workspace rotational --resolution-deg 10",
                                "workspace atlas --coarse"}) {
    for (const std::string n : {"1e12", "-5", "1000000000", "2.5", "nan"}) {
      const fs::path out = dir_ / "out";
      const CommandRun run = Robossis(cmd + " --out " + Q(out) + " --error-samples " + n);
      ExpectError(run, "--error-samples");
      EXPECT_FALSE(fs::exists(out)) << cmd << " " << n;
    }
  }
  ExpectError(Robossis("workspace dexterous --resolution-mm 10 --out " + Q(dir_ / "o") + " --error-samples 1e12"),
              "expected an integer from 0 to 100000 samples, got 1e+12");
}

TEST_F(HostileGeometryTest, DegenerateArmAnglesAreRefusedNamingTheFileAndKey) {
  const fs::path same = DataDirWithRsr("arm_angles_deg: [-30, 90, 210]", "arm_angles_deg: [90, 90, 90]");
  const CommandRun run = Robossis("--data-dir " + Q(same) + " robot info");
  ExpectError(run, "rsr.yaml");
  EXPECT_THAT(run.output, HasSubstr("geometry.arm_angles_deg: arms 1 and 2 are 0 deg apart; expected at least 30"));
}

TEST_F(HostileGeometryTest, ArmsCloserThan30DegreesAreRefused) {
  const fs::path close = DataDirWithRsr("arm_angles_deg: [-30, 90, 210]", "arm_angles_deg: [80, 90, 100]");
  ExpectError(Robossis("--data-dir " + Q(close) + " robot ik --pose 0,0,284,0,0,0"),
              "arms 1 and 2 are 10 deg apart");
  // Across the 360 deg wrap: 350 and 10 are 20 deg apart.
  const fs::path wrap = DataDirWithRsr("arm_angles_deg: [-30, 90, 210]", "arm_angles_deg: [350, 130, 10]");
  ExpectError(Robossis("--data-dir " + Q(wrap) + " robot info"), "arms 1 and 3 are 20 deg apart");
}

TEST_F(HostileGeometryTest, ANearSingularHomePoseIsRefused) {
  // A moving ring of 0.1 mm radius (cones widened so that home stays inside the limits): the legs meet at one point
  // and the ring is nearly free to turn about it (condition number 4.4e4).
  const fs::path data = DataDirWith("rsr.yaml", [](const std::string& t) {
    return Replace(Replace(t, "moving_ring_radius_m: 0.200", "moving_ring_radius_m: 0.0001"),
                   "spherical_cone_max_deg: 25", "spherical_cone_max_deg: 60");
  });
  ExpectError(Robossis("--data-dir " + Q(data) + " robot info"), "home_pose: the Jacobian's condition number");
}

TEST_F(HostileGeometryTest, PosesFarFromACoarseAtlasAreOffGrid) {
  const fs::path atlas = Atlas();
  // The coarse atlas has one position node in z (home, 284 mm): 400 mm above it no node answers.
  const CommandRun far = Robossis("workspace query --atlas " + Q(atlas) + " --pose 0,0,684,0,0,0 --json", false);
  ASSERT_EQ(far.exit_code, 0) << far.output;
  const nlohmann::json doc = nlohmann::json::parse(far.output);
  EXPECT_EQ(doc["status"]["rotation"], "off_grid") << far.output;
  EXPECT_TRUE(doc["signed_angle_deg"].is_null());
  EXPECT_TRUE(doc["rotational_slice_position_mm"].is_null());
  // One pitch node (0 deg): 20 deg of pitch is beyond the 5 deg cap.
  const CommandRun pitch = Robossis("workspace query --atlas " + Q(atlas) + " --pose 0,0,284,0,20,0 --json", false);
  ASSERT_EQ(pitch.exit_code, 0) << pitch.output;
  EXPECT_EQ(nlohmann::json::parse(pitch.output)["status"]["translation"], "off_grid") << pitch.output;
  // On the grid the answer stays "ok".
  const CommandRun home = Robossis("workspace query --atlas " + Q(atlas) + " --pose 0,0,284,0,0,0 --json", false);
  ASSERT_EQ(home.exit_code, 0) << home.output;
  EXPECT_EQ(nlohmann::json::parse(home.output)["status"]["translation"], "ok");
  EXPECT_EQ(nlohmann::json::parse(home.output)["status"]["rotation"], "ok");
}

TEST_F(HostileGeometryTest, APartialOrOlderManifestIsRefused) {
  const fs::path atlas = CopyOfAtlas();
  nlohmann::json m = nlohmann::json::parse(Read(atlas / "manifest.json"));
  ASSERT_EQ(m["version"], 3);
  // Every node is listed, empty ones too: 3 x 1 x 3 orientation nodes and 3 x 1 x 1 position nodes.
  ASSERT_EQ(m["dexterous_slices"].size(), 9u);
  ASSERT_EQ(m["rotational_slices"].size(), 3u);
  nlohmann::json truncated = m;
  truncated["dexterous_slices"].erase(truncated["dexterous_slices"].begin() + 2, truncated["dexterous_slices"].end());
  std::ofstream(atlas / "manifest.json") << truncated.dump();
  ExpectError(Robossis("workspace query --atlas " + Q(atlas) + " --pose 0,0,284,0,0,0"),
              "dexterous_slices: lists 2 of the grid's 9 nodes");
  // A node listed twice in place of another.
  nlohmann::json twice = m;
  twice["rotational_slices"][1] = twice["rotational_slices"][0];
  const fs::path other = CopyOfAtlas();
  std::ofstream(other / "manifest.json") << twice.dump();
  ExpectError(Robossis("workspace query --atlas " + Q(other) + " --pose 0,0,284,0,0,0"), "listed twice");
  // An atlas of version 2 (empty nodes omitted).
  nlohmann::json old = m;
  old["version"] = 2;
  const fs::path older = CopyOfAtlas();
  std::ofstream(older / "manifest.json") << old.dump();
  ExpectError(Robossis("workspace query --atlas " + Q(older) + " --pose 0,0,284,0,0,0"),
              "rebuild the atlas with `robossis workspace atlas`");
}

TEST_F(HostileGeometryTest, HugeOrNonFiniteWrenchesAreRefused) {
  const std::string statics = "robot statics --pose 0,0,284,0,0,0 --wrench ";
  ExpectError(Robossis(statics + "0,0,1e308,0,0,0"), "--wrench: FZ_N is 1e+308; expected a finite force");
  ExpectError(Robossis(statics + "1e308,1e308,-1e308,1e308,0,0"), "--wrench: FX_N");
  ExpectError(Robossis(statics + "0,0,0,0,0,2e5"), "TZ_NM is 200000; expected a finite moment within +/-100000 N m");
  ExpectError(Robossis(statics + "0,0,inf,0,0,0"), "--wrench");
  const CommandRun ok = Robossis(statics + "0,0,-517,0,0,0 --json", false);
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
}

}  // namespace
