// The boundary atlas: build, load, look up, reject corrupt folders.

#include "geometry/boundary_atlas.h"

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "src/core/files.h"
#include "src/core/pose.h"
#include "src/core/units.h"
#include "tests/support/alloc_counter.h"

namespace robossis::geometry {
namespace {

namespace fs = std::filesystem;

class AtlasTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() / ("robossis_atlas_test_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    const robot::RsrModel rsr = robot::RsrModel::Default();
    const robot::Sigma7Model hc = robot::Sigma7Model::Default();
    built_ = new BoundaryAtlas(BuildAtlas(rsr, hc, AtlasSpec::Coarse(rsr), *dir_));
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete built_;
    delete dir_;
  }
  // A copy of the atlas to damage.
  fs::path Copy(const std::string& name) const {
    const fs::path copy = dir_->string() + "_" + name;
    fs::remove_all(copy);
    fs::copy(*dir_, copy, fs::copy_options::recursive);
    return copy;
  }
  static fs::path* dir_;
  static BoundaryAtlas* built_;
};
fs::path* AtlasTest::dir_ = nullptr;
BoundaryAtlas* AtlasTest::built_ = nullptr;

std::string LoadError(const fs::path& dir) {
  try {
    BoundaryAtlas::Load(dir);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST_F(AtlasTest, LoadsWhatWasBuilt) {
  const BoundaryAtlas atlas = BoundaryAtlas::Load(*dir_);
  ASSERT_EQ(atlas.dexterous().size(), built_->dexterous().size());
  ASSERT_EQ(atlas.rotational().size(), built_->rotational().size());
  EXPECT_GT(atlas.dexterous().size(), 0u);
  EXPECT_GT(atlas.rotational().size(), 0u);
  for (std::size_t i = 0; i < atlas.dexterous().size(); ++i) {
    EXPECT_EQ(atlas.dexterous()[i].field->mesh().triangles, built_->dexterous()[i].field->mesh().triangles);
    EXPECT_NEAR(atlas.dexterous()[i].field->stats().volume, built_->dexterous()[i].field->stats().volume, 1e-12);
  }
  EXPECT_FALSE(fs::exists(dir_->string() + ".partial-" + std::to_string(::getpid())));
}

TEST_F(AtlasTest, LookupReturnsTheNearestNode) {
  // Coarse orientation grid: roll -10, 0, 10 deg; yaw -20, 0, 20 deg.
  const AtlasSlice* s = built_->FindDexterous({DegToRad(6), DegToRad(3), DegToRad(-12)});
  ASSERT_NE(s, nullptr);
  EXPECT_NEAR(s->fixed.x(), DegToRad(10), 1e-12);
  EXPECT_NEAR(s->fixed.y(), 0, 1e-12);
  EXPECT_NEAR(s->fixed.z(), DegToRad(-20), 1e-12);
  // Outside the grid: clamped to the edge node.
  const AtlasSlice* far = built_->FindDexterous({DegToRad(60), 0, 0});
  ASSERT_NE(far, nullptr);
  EXPECT_NEAR(far->fixed.x(), DegToRad(10), 1e-12);
}

TEST_F(AtlasTest, PoseQueryIsInsideAtHomeAndAllocatesNothing) {
  const robot::RsrModel rsr = robot::RsrModel::Default();
  AtlasPoseQuery query;
  PoseBoundaryResult r;
  query.Query(*built_, rsr.geometry().X_FM_home, 0.0, 0.0, &r);  // warm-up
  robossis::testing::AllocationCounter counter;
  query.Query(*built_, rsr.geometry().X_FM_home, 0.001, DegToRad(0.5), &r);
  EXPECT_EQ(counter.count(), 0u);
  ASSERT_EQ(r.translation.status, QueryStatus::kOk);
  ASSERT_EQ(r.rotation.status, QueryStatus::kOk);
  EXPECT_GT(r.translation.signed_distance, 0.03);   // home is deep inside (the default geometry reaches about +/-70 mm in z)
  EXPECT_GT(r.rotation.signed_distance, DegToRad(10));
}

TEST_F(AtlasTest, MissingManifestIsRejected) {
  const fs::path d = Copy("nomanifest");
  fs::remove(d / "manifest.json");
  EXPECT_NE(LoadError(d).find("manifest.json"), std::string::npos);
  fs::remove_all(d);
}

TEST_F(AtlasTest, TruncatedMeshIsRejectedNamingTheFile) {
  const fs::path d = Copy("truncated");
  const fs::path mesh = d / "dexterous" / "d_0_0_0.ply";
  fs::resize_file(mesh, fs::file_size(mesh) / 2);
  const std::string error = LoadError(d);
  EXPECT_NE(error.find("d_0_0_0.ply"), std::string::npos) << error;
  fs::remove_all(d);
}

TEST_F(AtlasTest, CorruptManifestIsRejected) {
  const fs::path d = Copy("badjson");
  WriteFileAtomically(d / "manifest.json", "{\"format\": \"robossis-boundary-atlas\", \"version\": 1, ");
  EXPECT_NE(LoadError(d).find("malformed"), std::string::npos);
  fs::remove_all(d);
}

// A manifest number that is no int (found by fuzz_atlas: converting 2.2e126 to int is undefined behaviour).
TEST_F(AtlasTest, ManifestNumberOutOfIntRangeIsRejectedNamingTheField) {
  const fs::path d = Copy("hugeversion");
  nlohmann::json m = nlohmann::json::parse(ReadTextFile(d / "manifest.json"));
  m["version"] = 2.2e126;
  WriteFileAtomically(d / "manifest.json", m.dump());
  EXPECT_NE(LoadError(d).find("version: expected an integer"), std::string::npos) << LoadError(d);
  m["version"] = nlohmann::json::parse(ReadTextFile(*dir_ / "manifest.json"))["version"];
  m["dexterous_slices"][0]["node"][1] = 1e300;
  WriteFileAtomically(d / "manifest.json", m.dump());
  EXPECT_NE(LoadError(d).find("node: expected an integer"), std::string::npos) << LoadError(d);
  fs::remove_all(d);
}

TEST_F(AtlasTest, FlippedByteIsDetected) {
  const fs::path d = Copy("flipped");
  const fs::path mesh = d / "rotational" / "r_0_0_0.ply";
  std::string bytes = ReadTextFile(mesh);
  bytes[bytes.size() / 2] ^= 0x10;
  WriteFileAtomically(mesh, bytes);
  EXPECT_NE(LoadError(d).find("hash"), std::string::npos);
  fs::remove_all(d);
}

TEST(AtlasSpecTest, InvalidGridIsRejected) {
  AtlasSpec s = AtlasSpec::Coarse(robot::RsrModel::Default());
  s.orientation_grid[0].step = 0;
  EXPECT_THROW(s.Validate(), std::invalid_argument);
  s = AtlasSpec::Coarse(robot::RsrModel::Default());
  s.dexterous_resolution_m = -1;
  EXPECT_THROW(s.Validate(), std::invalid_argument);
}

// A one-node axis (coarse: pitch 0, position y and z at home) covers only the cap, not its placeholder step.
TEST_F(AtlasTest, CoverageBeyondTheEndNodesIsCappedAt5DegAnd15Mm) {
  const BoundaryAtlas atlas = BoundaryAtlas::Load(*dir_);
  const Eigen::Vector3d home = robot::RsrModel::Default().geometry().X_FM_home.translation();
  EXPECT_TRUE(atlas.CoversOrientation({0, DegToRad(4.9), 0}));
  EXPECT_FALSE(atlas.CoversOrientation({0, DegToRad(5.1), 0}));
  EXPECT_TRUE(atlas.CoversPosition(home + Eigen::Vector3d(0, 0, 0.0149)));
  EXPECT_FALSE(atlas.CoversPosition(home + Eigen::Vector3d(0, 0, 0.0151)));
  // Yaw -20..20 step 20 deg: half a step is 10 deg, capped to 5; inside the span every pose is covered.
  EXPECT_TRUE(atlas.CoversOrientation({0, 0, DegToRad(10)}));
  EXPECT_FALSE(atlas.CoversOrientation({0, 0, DegToRad(25.5)}));
  PoseBoundaryResult r;
  r.translation.status = r.rotation.status = QueryStatus::kOk;
  MarkOffGrid(&atlas, PoseFromMmDeg((Vector6d() << 0, 0, 684, 0, 0, 0).finished()), &r);
  EXPECT_EQ(r.translation.status, QueryStatus::kOk);
  EXPECT_EQ(r.rotation.status, QueryStatus::kOffGrid);
  EXPECT_STREQ(ToString(QueryStatus::kOffGrid), "off_grid");
}

TEST_F(AtlasTest, ManifestListsEveryNodeAndAPartialOneIsRefused) {
  const nlohmann::json m = nlohmann::json::parse(ReadTextFile(*dir_ / "manifest.json"));
  EXPECT_EQ(m["version"], 3);
  EXPECT_EQ(m["dexterous_slices"].size(), 9u);
  EXPECT_EQ(m["rotational_slices"].size(), 3u);
  const fs::path d = Copy("partial");
  nlohmann::json partial = m;
  partial["rotational_slices"].erase(partial["rotational_slices"].begin());
  WriteFileAtomically(d / "manifest.json", partial.dump());
  EXPECT_NE(LoadError(d).find("rotational_slices: lists 2 of the grid's 3 nodes"), std::string::npos) << LoadError(d);
  fs::remove_all(d);
}

}  // namespace
}  // namespace robossis::geometry

namespace robossis::geometry {
namespace {

TEST(AtlasHashTest, Fnv1aUsesTheStandardOffsetBasis) {
  // Published FNV-1a 64-bit test vectors: "" is the offset basis itself; "a" and "foobar".
  EXPECT_EQ(Fnv1a64Hex(""), "cbf29ce484222325");
  EXPECT_EQ(Fnv1a64Hex("a"), "af63dc4c8601ec8c");
  EXPECT_EQ(Fnv1a64Hex("foobar"), "85944171f73967e8");
}

TEST_F(AtlasTest, RefusesAnotherGeometryAndKnowsItsGrid) {
  const robot::RsrModel rsr = robot::RsrModel::Default();
  const robot::Sigma7Model hc = robot::Sigma7Model::Default();
  const BoundaryAtlas atlas = BoundaryAtlas::Load(*dir_);
  EXPECT_NO_THROW(atlas.RequireBuiltFor(rsr, hc, "atlas"));
  robot::RsrGeometry other = rsr.geometry();
  other.limits.rotary_max_rad *= 0.9;
  try {
    atlas.RequireBuiltFor(robot::RsrModel(other), hc, "atlas");
    FAIL() << "an atlas of other limits was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("built for another robot geometry"), std::string::npos);
  }
  // Coarse orientation grid: roll -10..10 deg; 60 deg is far off it, 12 deg within half a step.
  EXPECT_FALSE(atlas.CoversOrientation({DegToRad(60), 0, 0}));
  EXPECT_TRUE(atlas.CoversOrientation({DegToRad(12), 0, 0}));
  EXPECT_TRUE(atlas.CoversPosition(rsr.geometry().X_FM_home.translation()));
  EXPECT_FALSE(atlas.CoversPosition(rsr.geometry().X_FM_home.translation() + Eigen::Vector3d(1.0, 0, 0)));
}

}  // namespace
}  // namespace robossis::geometry
