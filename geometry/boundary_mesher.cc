// Flying edges on the node feasibility, then bisection of every vertex along its grid edge.

#include "geometry/boundary_mesher.h"

#include <cmath>
#include <stdexcept>

#include <vtkCellArray.h>
#include <vtkFlyingEdges3D.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

namespace robossis::geometry {

namespace {

bool TouchesFaces(const VoxelGrid& g) {
  const Eigen::Vector3i& n = g.dims;
  for (int k = 0; k < n.z(); ++k) {
    for (int j = 0; j < n.y(); ++j) {
      for (int i = 0; i < n.x(); ++i) {
        const bool face = i == 0 || j == 0 || k == 0 || i == n.x() - 1 || j == n.y() - 1 || k == n.z() - 1;
        if (face && g.feasible[g.Index(i, j, k)]) return true;
      }
    }
  }
  return false;
}

}  // namespace

BoundaryMeshResult ExtractBoundaryMesh(const VoxelGrid& grid, const FeasibilityFn& feasible, double tolerance) {
  if (!(tolerance > 0)) throw std::invalid_argument("ExtractBoundaryMesh: tolerance must be > 0");
  if (grid.dims.minCoeff() < 3 || grid.feasible.size() != static_cast<std::size_t>(grid.dims.prod())) {
    throw std::invalid_argument("ExtractBoundaryMesh: grid needs at least 3 nodes per axis and one value per node");
  }
  if (TouchesFaces(grid)) {
    throw std::invalid_argument("ExtractBoundaryMesh: a feasible node lies on the grid's faces; the boundary would "
                                "not close (enlarge the search box)");
  }
  // The image in index coordinates (origin 0, spacing 1): vertex positions then identify their grid edge exactly.
  vtkNew<vtkImageData> image;
  image->SetDimensions(grid.dims.x(), grid.dims.y(), grid.dims.z());
  image->SetOrigin(0, 0, 0);
  image->SetSpacing(1, 1, 1);
  vtkNew<vtkFloatArray> values;
  values->SetName("feasible");
  values->SetNumberOfTuples(static_cast<vtkIdType>(grid.feasible.size()));
  for (std::size_t n = 0; n < grid.feasible.size(); ++n) {
    values->SetValue(static_cast<vtkIdType>(n), grid.feasible[n] ? 1.0f : 0.0f);
  }
  image->GetPointData()->SetScalars(values);

  vtkNew<vtkFlyingEdges3D> flying_edges;
  flying_edges->SetInputData(image);
  flying_edges->SetNumberOfContours(1);
  flying_edges->SetValue(0, 0.5);
  flying_edges->ComputeNormalsOff();
  flying_edges->ComputeGradientsOff();
  flying_edges->ComputeScalarsOff();
  flying_edges->Update();
  vtkPolyData* poly = flying_edges->GetOutput();

  BoundaryMeshResult result;
  const vtkIdType n_points = poly->GetNumberOfPoints();
  result.mesh.vertices.resize(static_cast<std::size_t>(n_points));
  for (vtkIdType id = 0; id < n_points; ++id) {
    double x[3];
    poly->GetPoint(id, x);
    // Exactly one coordinate is fractional (k + 0.5): that is the axis of the crossing edge.
    int axis = -1;
    Eigen::Vector3i lo_index;
    for (int a = 0; a < 3; ++a) {
      const double f = x[a] - std::floor(x[a]);
      if (std::abs(f - 0.5) < 0.25) {
        axis = a;
        lo_index[a] = static_cast<int>(std::floor(x[a]));
      } else {
        lo_index[a] = static_cast<int>(std::lround(x[a]));
      }
    }
    if (axis < 0) throw std::logic_error("ExtractBoundaryMesh: a flying-edges vertex is not on a grid edge");
    Eigen::Vector3i hi_index = lo_index;
    hi_index[axis] += 1;
    Eigen::Vector3d inside = grid.Node(lo_index.x(), lo_index.y(), lo_index.z());
    Eigen::Vector3d outside = grid.Node(hi_index.x(), hi_index.y(), hi_index.z());
    if (!grid.feasible[grid.Index(lo_index.x(), lo_index.y(), lo_index.z())]) std::swap(inside, outside);
    // Bisection: `inside` stays feasible, `outside` infeasible.
    while ((outside - inside).norm() > tolerance) {
      const Eigen::Vector3d mid = 0.5 * (inside + outside);
      ++result.bisection_calls;
      (feasible(mid) ? inside : outside) = mid;
    }
    result.max_bracket = std::max(result.max_bracket, (outside - inside).norm());
    result.mesh.vertices[static_cast<std::size_t>(id)] = 0.5 * (inside + outside);
  }
  vtkCellArray* polys = poly->GetPolys();
  result.mesh.triangles.reserve(static_cast<std::size_t>(polys->GetNumberOfCells()));
  vtkNew<vtkIdList> cell;
  polys->InitTraversal();
  while (polys->GetNextCell(cell)) {
    if (cell->GetNumberOfIds() != 3) throw std::logic_error("ExtractBoundaryMesh: flying edges gave a non-triangle");
    result.mesh.triangles.emplace_back(static_cast<int>(cell->GetId(0)), static_cast<int>(cell->GetId(1)),
                                       static_cast<int>(cell->GetId(2)));
  }
  if (SignedVolume(result.mesh) < 0) FlipOrientation(result.mesh);
  return result;
}

}  // namespace robossis::geometry
