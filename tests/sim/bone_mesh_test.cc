// The femur mesh, its mid-shaft cut into two closed fragments, and the mass properties used for the ring's inertia.

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "robot/sim/bone_mesh.h"
#include "sim_fixture.h"

namespace robossis::sim {
namespace {

// Every directed edge appears once and its reverse once: closed, consistently oriented 2-manifold.
bool IsClosedOriented(const TriangleMesh& mesh) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;
    const auto reverse = directed.find({edge.second, edge.first});
    if (reverse == directed.end() || reverse->second != 1) return false;
  }
  return true;
}

TriangleMesh UnitCube() {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  // Outward faces, two triangles each.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

TEST(BoneMeshTest, UnitCubeMassPropertiesMatchTheClosedForm) {
  // Reference: a unit cube has volume 1, centroid (0.5, 0.5, 0.5), and I = 1/6 about each centroidal axis.
  const MassProperties mp = CalcMassProperties(UnitCube());
  EXPECT_NEAR(mp.volume_m3, 1.0, 1e-12);
  EXPECT_TRUE(mp.centroid.isApprox(Eigen::Vector3d(0.5, 0.5, 0.5), 1e-12));
  EXPECT_TRUE(mp.inertia_per_density.isApprox(Eigen::Matrix3d::Identity() / 6.0, 1e-12));
}

TEST(BoneMeshTest, CutCubeGivesTwoClosedHalves) {
  const CutMesh cut = CutMeshAtZ(UnitCube(), 0.3);
  EXPECT_TRUE(IsClosedOriented(cut.below));
  EXPECT_TRUE(IsClosedOriented(cut.above));
  EXPECT_NEAR(CalcMassProperties(cut.below).volume_m3, 0.3, 1e-12);
  EXPECT_NEAR(CalcMassProperties(cut.above).volume_m3, 0.7, 1e-12);
  EXPECT_EQ(cut.loops, 1);
}

TEST(BoneMeshTest, FemurMatchesItsReadme) {
  // data/femur/README.md: closed, 7,349 vertices, 14,694 triangles, volume about 503 cm^3, z from -313.9 to 109.8 mm.
  const TriangleMesh femur = ReadStl(testing::Data().config.bone.mesh_file);
  EXPECT_EQ(femur.vertices.size(), 7349u);
  EXPECT_EQ(femur.triangles.size(), 14694u);
  EXPECT_TRUE(IsClosedOriented(femur));
  EXPECT_NEAR(CalcMassProperties(femur).volume_m3 * 1e6, 503.0, 1.0);
}

TEST(BoneMeshTest, MidShaftCutGivesClosedFragmentsThatKeepTheVolume) {
  const TriangleMesh femur = ReadStl(testing::Data().config.bone.mesh_file);
  const CutMesh cut = CutMeshAtZ(femur, testing::Data().config.bone.cut_z_mesh_m);
  EXPECT_EQ(cut.loops, 1);  // one shaft cross-section
  EXPECT_TRUE(IsClosedOriented(cut.below));
  EXPECT_TRUE(IsClosedOriented(cut.above));
  const double v = CalcMassProperties(femur).volume_m3;
  const double v_parts = CalcMassProperties(cut.below).volume_m3 + CalcMassProperties(cut.above).volume_m3;
  EXPECT_NEAR(v_parts, v, 1e-9 * v);
}

TEST(BoneMeshTest, PlacedFragmentsMeetAtTheFractureSiteOnTheRobotAxis) {
  const BoneFragments& f = testing::Data().fragments;
  EXPECT_NEAR(f.fracture_site_F.z(), testing::Data().config.bone.fracture_site_z_m, 1e-12);
  double proximal_top = -1, distal_bottom = 1;
  for (const auto& v : f.proximal_F.vertices) proximal_top = std::max(proximal_top, v.z());
  const Eigen::Isometry3d X_FM = testing::Data().model.geometry().X_FM_home;
  for (const auto& v : f.distal_M.vertices) distal_bottom = std::min(distal_bottom, (X_FM * v).z());
  EXPECT_NEAR(proximal_top, f.fracture_site_F.z(), 1e-9);
  EXPECT_NEAR(distal_bottom, f.fracture_site_F.z(), 1e-9);
}

TEST(BoneMeshTest, MissingOrEmptyStlNamesTheFile) {
  try {
    ReadStl("/nonexistent/bone.stl");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/bone.stl"), std::string::npos) << e.what();
  }
}

TEST(BoneMeshTest, ABinaryStlWithANonFiniteCoordinateOrADirectoryIsRefused) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "bone_mesh_test";
  std::filesystem::create_directories(dir);
  // One facet: normal, three vertices, attribute count; the second vertex's y is NaN.
  std::string stl(80, ' ');
  const std::uint32_t count = 1;
  stl.append(reinterpret_cast<const char*>(&count), 4);
  const float facet[12] = {0, 0, 1, 0, 0, 0, 1, std::nanf(""), 0, 0, 1, 0};
  stl.append(reinterpret_cast<const char*>(facet), sizeof facet);
  stl.append(2, '\0');
  const std::filesystem::path file = dir / "nan.stl";
  std::ofstream(file, std::ios::binary) << stl;
  try {
    ReadStl(file);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("facet 1 vertex 2: expected three finite coordinates"), std::string::npos)
        << e.what();
  }
  try {
    ReadStl(dir);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("expected a regular file"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace robossis::sim
