#pragma once
// A closed triangle mesh (the boundary of one workspace slice), its statistics, and its files.
//
// Units: a mesh holds coordinates in the slice's SI units: metres for position slices, radians for
// roll-pitch-yaw slices (see workspace_slice.h). Files hold the edge units instead: millimetres or degrees, the
// scale given by MeshFileScale(), so that MeshLab/ParaView show numbers people recognise.

#include <cstdint>
#include <filesystem>
#include <vector>

#include <Eigen/Core>

namespace robossis::geometry {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  // Counter-clockwise seen from outside: the right-hand normal (v1 - v0) x (v2 - v0) points out of the region.
  std::vector<Eigen::Vector3i> triangles;
};

struct MeshStatistics {
  double volume = 0;                                        // enclosed volume (units^3), by the divergence theorem
  Eigen::Vector3d min = Eigen::Vector3d::Zero();            // axis-aligned extents
  Eigen::Vector3d max = Eigen::Vector3d::Zero();
  std::size_t triangles = 0;
  std::size_t vertices = 0;
  bool watertight = false;          // every undirected edge is shared by exactly two triangles
  bool consistently_oriented = false;  // every edge is traversed once in each direction by its two triangles
  bool outward = false;             // consistently oriented and the signed volume is positive
  std::size_t degenerate_triangles = 0;  // zero-area triangles (kept; they do not break the queries)
};

MeshStatistics ComputeMeshStatistics(const TriangleMesh& mesh);

// The directed edges of a mesh grouped by their start vertex (compressed rows): edge e of triangle t runs from
// triangles[t][e] to triangles[t][(e + 1) % 3]. Lookups scan one vertex's few edges, which is several times faster
// than hashing every edge -- it matters when a slice is rebuilt while the hand moves. Indices must be valid.
class DirectedEdges {
 public:
  explicit DirectedEdges(const TriangleMesh& mesh);
  int Count(int from, int to) const noexcept;  // how many triangles traverse from -> to
  int Owner(int from, int to) const noexcept;  // a triangle that traverses from -> to, or -1

 private:
  std::vector<int> row_start_;  // per vertex, into to_/triangle_ (size vertices + 1)
  std::vector<int> to_, triangle_;
};
// The signed enclosed volume alone (positive for an outward-oriented closed mesh); cheaper than the statistics.
double SignedVolume(const TriangleMesh& mesh);

// Reverses every triangle (turns an inward-oriented mesh outward).
void FlipOrientation(TriangleMesh& mesh);

// Binary STL (float32) and binary little-endian PLY (float32 vertices, int32 indices). Coordinates are multiplied
// by `file_scale` on writing and divided by it on reading. Written atomically; throw std::runtime_error on failure.
void WriteBinaryStl(const TriangleMesh& mesh, double file_scale, const std::filesystem::path& file);
void WriteBinaryPly(const TriangleMesh& mesh, double file_scale, const std::filesystem::path& file);
std::string BinaryStlBytes(const TriangleMesh& mesh, double file_scale);
std::string BinaryPlyBytes(const TriangleMesh& mesh, double file_scale);

// Reads a binary PLY written by WriteBinaryPly. Throws std::runtime_error naming the file and what is wrong
// (truncated, wrong header, index out of range, non-finite coordinate).
TriangleMesh ReadBinaryPly(const std::filesystem::path& file, double file_scale);
TriangleMesh ParseBinaryPly(const std::string& bytes, double file_scale, const std::string& name_for_errors);

}  // namespace robossis::geometry
