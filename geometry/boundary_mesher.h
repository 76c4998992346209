#pragma once
// Voxel feasibility -> closed triangle mesh: VTK flying edges (vtkFlyingEdges3D) on the 0/1 feasibility of the grid
// nodes gives the topology (one vertex on every grid edge whose ends differ); each vertex is then moved onto the
// true boundary by bisection of the feasibility along its grid edge.

#include <functional>

#include "geometry/triangle_mesh.h"
#include "geometry/workspace_slice.h"

namespace robossis::geometry {

using FeasibilityFn = std::function<bool(const Eigen::Vector3d&)>;

struct BoundaryMeshResult {
  TriangleMesh mesh;          // outward oriented
  double max_bracket = 0;     // largest final bisection bracket (slice units): every vertex is within half of it
  std::size_t bisection_calls = 0;
};

// `grid.feasible` must be 0 on every face of the grid (the region is strictly inside), else the surface would not
// close; throws std::invalid_argument otherwise. `tolerance` (> 0): the bisection stops when the bracket is below it.
BoundaryMeshResult ExtractBoundaryMesh(const VoxelGrid& grid, const FeasibilityFn& feasible, double tolerance);

}  // namespace robossis::geometry
