#pragma once
// Triangle meshes of the femur: STL reading (vertices welded), a plane cut into two closed fragments with flat cap
// faces, mass properties of a closed mesh, and the point sets of the convex slabs used as Bullet collision hulls.

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace robossis::sim {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;  // counter-clockwise seen from outside (outward normals)

  void Transform(const Eigen::Isometry3d& X);
};

// The size bound of an STL file: 80 times the shipped femur (FemurR.stl, 3.3 MB), far below the machine's memory.
inline constexpr std::uintmax_t kMaxStlFileBytes = std::uintmax_t{256} << 20;  // 256 MiB

// Reads an ASCII or binary STL (through ReadBoundedFile: a regular file within kMaxStlFileBytes); vertices with
// identical coordinates are merged. Throws std::runtime_error naming the file on a missing or non-regular file, a
// malformed line, a non-finite coordinate or an empty mesh.
TriangleMesh ReadStl(const std::filesystem::path& file);

// ASCII STL text; `header` goes on the `solid` line (used to mark altered meshes).
std::string StlAscii(const TriangleMesh& mesh, const std::string& header);

// Volume, centroid and the inertia tensor about the centroid per unit density, of a closed mesh with outward
// normals (divergence theorem over the signed tetrahedra from the origin).
struct MassProperties {
  double volume_m3 = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia_per_density = Eigen::Matrix3d::Zero();  // m^5
};
MassProperties CalcMassProperties(const TriangleMesh& mesh);

// A closed mesh cut by the plane z = z_cut: the part below and the part above, each closed by a flat cap
// (triangle fan from the centroid of each cut loop; the mid-shaft loops are star-shaped about it).
struct CutMesh {
  TriangleMesh below;
  TriangleMesh above;
  Eigen::Vector3d cap_centroid = Eigen::Vector3d::Zero();  // centroid of the (largest) cut loop
  int loops = 0;
};
// Throws std::invalid_argument if the plane misses the mesh or an open edge is found on the cut.
CutMesh CutMeshAtZ(const TriangleMesh& mesh, double z_cut);

// Points of the mesh surface (triangles clipped to each slab) in slabs of height `slab_height` covering
// [z_from, z_to]: the convex hull of each set is one convex piece of the collision model.
std::vector<std::vector<Eigen::Vector3d>> SlabPointSets(const TriangleMesh& mesh, double z_from, double z_to,
                                                        double slab_height);

}  // namespace robossis::sim
