// Mesh statistics and files.

#include "geometry/triangle_mesh.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "tests/geometry/test_meshes.h"

namespace robossis::geometry {
namespace {

TEST(TriangleMeshTest, BoxStatistics) {
  const TriangleMesh box = testing::BoxMesh({0, 0, 0}, {1, 2, 3});
  const MeshStatistics s = ComputeMeshStatistics(box);
  EXPECT_NEAR(s.volume, 6.0, 1e-12);  // 1 x 2 x 3
  EXPECT_TRUE(s.watertight);
  EXPECT_TRUE(s.consistently_oriented);
  EXPECT_TRUE(s.outward);
  EXPECT_EQ(s.triangles, 12u);
  EXPECT_TRUE(s.max.isApprox(Eigen::Vector3d(1, 2, 3)));
}

TEST(TriangleMeshTest, FlippedBoxIsNotOutward) {
  TriangleMesh box = testing::BoxMesh({0, 0, 0}, {1, 1, 1});
  FlipOrientation(box);
  const MeshStatistics s = ComputeMeshStatistics(box);
  EXPECT_TRUE(s.watertight);
  EXPECT_FALSE(s.outward);
  EXPECT_NEAR(s.volume, -1.0, 1e-12);
}

TEST(TriangleMeshTest, OpenMeshIsNotWatertight) {
  TriangleMesh box = testing::BoxMesh({0, 0, 0}, {1, 1, 1});
  box.triangles.pop_back();
  EXPECT_FALSE(ComputeMeshStatistics(box).watertight);
}

TEST(TriangleMeshTest, InconsistentOrientationIsDetected) {
  TriangleMesh box = testing::BoxMesh({0, 0, 0}, {1, 1, 1});
  std::swap(box.triangles[0][1], box.triangles[0][2]);
  const MeshStatistics s = ComputeMeshStatistics(box);
  EXPECT_TRUE(s.watertight);
  EXPECT_FALSE(s.consistently_oriented);
}

TEST(TriangleMeshTest, PlyRoundTripInEdgeUnits) {
  const TriangleMesh sphere = testing::IcoSphere(2, 0.1);
  const std::string bytes = BinaryPlyBytes(sphere, 1000.0);
  const TriangleMesh back = ParseBinaryPly(bytes, 1000.0, "sphere.ply");
  ASSERT_EQ(back.vertices.size(), sphere.vertices.size());
  ASSERT_EQ(back.triangles, sphere.triangles);
  for (std::size_t i = 0; i < back.vertices.size(); ++i) {
    EXPECT_LT((back.vertices[i] - sphere.vertices[i]).norm(), 1e-8);  // float32 in mm
  }
}

TEST(TriangleMeshTest, StlHasTheBinaryLayout) {
  const TriangleMesh box = testing::BoxMesh({0, 0, 0}, {1, 1, 1});
  EXPECT_EQ(BinaryStlBytes(box, 1.0).size(), 84u + 50u * 12u);  // 80-byte header, count, 50 bytes per triangle
}

TEST(TriangleMeshTest, TruncatedPlyIsRejected) {
  const std::string bytes = BinaryPlyBytes(testing::BoxMesh({0, 0, 0}, {1, 1, 1}), 1.0);
  EXPECT_THROW(
      {
        try {
          ParseBinaryPly(bytes.substr(0, bytes.size() - 5), 1.0, "box.ply");
        } catch (const std::runtime_error& e) {
          EXPECT_NE(std::string(e.what()).find("box.ply"), std::string::npos);
          EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos);
          throw;
        }
      },
      std::runtime_error);
}

TEST(TriangleMeshTest, GarbagePlyIsRejected) {
  EXPECT_THROW(ParseBinaryPly("hello", 1.0, "x.ply"), std::runtime_error);
  std::string bytes = BinaryPlyBytes(testing::BoxMesh({0, 0, 0}, {1, 1, 1}), 1.0);
  bytes[bytes.size() - 2] = 0x7f;  // last index far out of range
  EXPECT_THROW(ParseBinaryPly(bytes, 1.0, "x.ply"), std::runtime_error);
}

// Found by fuzz_atlas: 12 × 2^62 wraps to 0, so an empty body "matched" 2^62 vertices and the reader tried to
// allocate them (std::length_error, not a message).
TEST(TriangleMeshTest, PlyCountsAreBoundedByTheFileBeforeTheyAreMultiplied) {
  auto ply = [](const std::string& elements) {
    return "ply\nformat binary_little_endian 1.0\n" + elements + "property list uchar int vertex_indices\nend_header\n";
  };
  auto error = [](const std::string& bytes) {
    try {
      ParseBinaryPly(bytes, 1.0, "slice.ply");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error(ply("element vertex 4611686018427387904\nelement face 0\n")),
            "slice.ply: 0 bytes after the header; expected 12 per vertex and 13 per triangle for 4611686018427387904 "
            "vertices and 0 triangles (truncated?)");
  EXPECT_EQ(error(ply("element vertex 1\nelement vertex 2\nelement face 0\n")),
            "slice.ply: 'element vertex' appears twice in the header");
  EXPECT_EQ(error(ply("element vertex 99999999999999999999\nelement face 0\n")),
            "slice.ply: 'element vertex 99999999999999999999': expected a count from 0 to 9223372036854775807");
  EXPECT_EQ(error(ply("element vertex 0\nelement face 0\n")), "no error");
}

}  // namespace
}  // namespace robossis::geometry
