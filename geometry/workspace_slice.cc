// Workspace slices: grid sampling of the feasibility, then the boundary mesher.

#include "geometry/workspace_slice.h"

#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "geometry/boundary_mesher.h"
#include "geometry/dexterous_row_bounds.h"
#include "robot/rsr_kinematics.h"
#include "src/core/pose.h"
#include "src/core/units.h"

namespace robossis::geometry {

namespace {

double SecondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string Vec(const Eigen::Vector3d& v, double scale) {
  return std::to_string(v.x() * scale) + "," + std::to_string(v.y() * scale) + "," + std::to_string(v.z() * scale);
}

// Samples the feasibility on the grid covering `box`; returns the number of feasible nodes and whether one lies on
// a face of the grid, and adds the nodes tested to *evaluations. A dexterous slice tests only the nodes its rows'
// bounds leave (DexterousRowBounds: every other node is infeasible, so the grid is the same).
std::size_t SampleGrid(const robot::RsrModel& rsr, const SliceFeasibility& feasible, const Eigen::AlignedBox3d& box,
                       double spacing, VoxelGrid* grid, bool* touches_faces, std::size_t* evaluations) {
  grid->spacing = spacing;
  grid->origin = box.min();
  const Eigen::Vector3d size = box.max() - box.min();
  for (int a = 0; a < 3; ++a) grid->dims[a] = static_cast<int>(std::ceil(size[a] / spacing)) + 1;
  const double n_nodes = static_cast<double>(grid->dims.x()) * grid->dims.y() * grid->dims.z();
  if (n_nodes > 4.0e8) {
    throw std::invalid_argument("resolution " + std::to_string(spacing) + " is too fine for the search box (" +
                                std::to_string(n_nodes) + " grid nodes; at most 4e8)");
  }
  grid->feasible.assign(static_cast<std::size_t>(n_nodes), 0);
  std::optional<DexterousRowBounds> rows;
  if (feasible.kind() == SliceKind::kRsrDexterous) rows.emplace(rsr, RotationFromRpy(feasible.fixed()));
  std::size_t count = 0;
  *touches_faces = false;
  const Eigen::Vector3i& n = grid->dims;
  for (int k = 0; k < n.z(); ++k) {
    for (int j = 0; j < n.y(); ++j) {
      int first = 0, last = n.x() - 1;
      if (rows) {
        const Eigen::Vector3d row = grid->Node(0, j, k);
        if (!rows->Candidates(row.y(), row.z(), row.x(), spacing, n.x(), &first, &last)) continue;
      }
      *evaluations += static_cast<std::size_t>(last - first + 1);
      for (int i = first; i <= last; ++i) {
        if (!feasible(grid->Node(i, j, k))) continue;
        grid->feasible[grid->Index(i, j, k)] = 1;
        ++count;
        if (i == 0 || j == 0 || k == 0 || i == n.x() - 1 || j == n.y() - 1 || k == n.z() - 1) *touches_faces = true;
      }
    }
  }
  return count;
}

}  // namespace

const char* ToString(SliceKind kind) {
  switch (kind) {
    case SliceKind::kRsrDexterous: return "rsr_dexterous";
    case SliceKind::kRsrRotational: return "rsr_rotational";
    case SliceKind::kHcTranslation: return "hc_translation";
    case SliceKind::kHcWrist: return "hc_wrist";
  }
  return "unknown";
}

SliceKind SliceKindFromString(const std::string& s) {
  for (SliceKind k : {SliceKind::kRsrDexterous, SliceKind::kRsrRotational, SliceKind::kHcTranslation,
                      SliceKind::kHcWrist}) {
    if (s == ToString(k)) return k;
  }
  throw std::invalid_argument("unknown slice kind '" + s +
                              "' (expected rsr_dexterous, rsr_rotational, hc_translation or hc_wrist)");
}

bool IsAngularSlice(SliceKind kind) { return kind == SliceKind::kRsrRotational || kind == SliceKind::kHcWrist; }
double EdgeUnitScale(SliceKind kind) { return IsAngularSlice(kind) ? kRadToDeg : kMToMm; }
const char* EdgeUnitName(SliceKind kind) { return IsAngularSlice(kind) ? "deg" : "mm"; }

SliceFeasibility::SliceFeasibility(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, SliceKind kind,
                                   const Eigen::Vector3d& fixed)
    : rsr_(&rsr), hc_(&hc), kind_(kind), fixed_(fixed) {
  if (kind == SliceKind::kRsrDexterous) R_fixed_ = RotationFromRpy(fixed);
}

bool SliceFeasibility::operator()(const Eigen::Vector3d& q) const noexcept {
  switch (kind_) {
    case SliceKind::kRsrDexterous: {
      Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
      X.linear() = R_fixed_;
      X.translation() = q;
      return robot::IsPoseFeasible(*rsr_, X);
    }
    case SliceKind::kRsrRotational: {
      Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
      X.linear() = RotationFromRpy(q);
      X.translation() = fixed_;
      return robot::IsPoseFeasible(*rsr_, X);
    }
    case SliceKind::kHcTranslation: return robot::CalcDeltaInverseKinematics(*hc_, q).within_limits;
    case SliceKind::kHcWrist: return robot::WristWithinRange(*hc_, q);
  }
  return false;
}

Eigen::AlignedBox3d DefaultSearchBox(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, const SliceSpec& spec) {
  // Assumptions: boxes that hold the default geometry's slices (the default geometry's reach, README.md "The RSR model": about +/-130 mm in x, y, +/-70 mm
  // in z, +/-20 deg tilt, +/-39 deg twist); GenerateSlice grows them when a slice touches a face.
  switch (spec.kind) {
    case SliceKind::kRsrDexterous: {
      const Eigen::Vector3d c = rsr.geometry().X_FM_home.translation();
      const Eigen::Vector3d half(0.16, 0.16, 0.10);
      return {c - half, c + half};
    }
    case SliceKind::kRsrRotational: {
      const Eigen::Vector3d half(DegToRad(32), DegToRad(32), DegToRad(50));
      return {-half, half};
    }
    case SliceKind::kHcTranslation: {
      const Eigen::Vector3d half = Eigen::Vector3d::Constant(0.15);
      return {hc.p_center_O() - half, hc.p_center_O() + half};
    }
    case SliceKind::kHcWrist: {
      const Eigen::Vector3d half = hc.geometry().wrist_half_range_rad * 1.1 + Eigen::Vector3d::Constant(DegToRad(5));
      return {-half, half};
    }
  }
  return {};
}

WorkspaceSlice GenerateSlice(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, const SliceSpec& spec,
                             const SliceOptions& options) {
  const std::string unit = EdgeUnitName(spec.kind);
  const double scale = EdgeUnitScale(spec.kind);
  if (!std::isfinite(spec.resolution) || spec.resolution <= 0) {
    throw std::invalid_argument(std::string(ToString(spec.kind)) + " slice: resolution must be a positive number of " +
                                unit + ", got " + std::to_string(spec.resolution * scale));
  }
  if (!spec.fixed.allFinite()) throw std::invalid_argument(std::string(ToString(spec.kind)) + " slice: non-finite pose");
  WorkspaceSlice slice;
  slice.spec = spec;
  const SliceFeasibility feasible(rsr, hc, spec.kind, spec.fixed);
  Eigen::AlignedBox3d box = DefaultSearchBox(rsr, hc, spec);
  const Eigen::Vector3d box_size = box.max() - box.min();
  if ((box_size.array() < 2 * spec.resolution).any()) {
    throw std::invalid_argument(std::string(ToString(spec.kind)) + " slice: resolution " +
                                std::to_string(spec.resolution * scale) + " " + unit +
                                " is coarser than half the search box (" + Vec(box_size, scale) + " " + unit + ")");
  }
  auto t0 = std::chrono::steady_clock::now();
  bool touches = false;
  for (int growth = 0;; ++growth) {
    slice.grid_evaluations = 0;  // the last grid's
    slice.feasible_nodes =
        SampleGrid(rsr, feasible, box, spec.resolution, &slice.grid, &touches, &slice.grid_evaluations);
    if (!touches) break;
    if (growth == options.max_box_growths) {
      throw std::runtime_error(std::string(ToString(spec.kind)) + " slice: the feasible region still touches the "
                               "search box after " + std::to_string(growth) + " growths (box " +
                               Vec(box.min(), scale) + " .. " + Vec(box.max(), scale) + " " + unit + ")");
    }
    const Eigen::Vector3d half = 0.5 * (box.max() - box.min());
    box = Eigen::AlignedBox3d(box.min() - half, box.max() + half);
  }
  slice.seconds_grid = SecondsSince(t0);
  if (slice.feasible_nodes == 0) {
    const std::string fixed_name = IsAngularSlice(spec.kind) ? "position (mm) " + Vec(spec.fixed, kMToMm)
                                                             : "orientation (deg) " + Vec(spec.fixed, kRadToDeg);
    throw std::runtime_error(std::string(ToString(spec.kind)) + " slice is empty: no feasible grid node at " +
                             fixed_name + " and resolution " + std::to_string(spec.resolution * scale) + " " + unit +
                             " (the fixed pose is unreachable, or the region is thinner than the resolution)");
  }
  t0 = std::chrono::steady_clock::now();
  const double tolerance =
      IsAngularSlice(spec.kind) ? options.refine_tolerance_angle_rad : options.refine_tolerance_position_m;
  BoundaryMeshResult meshed = ExtractBoundaryMesh(
      slice.grid, [&feasible](const Eigen::Vector3d& q) { return feasible(q); }, tolerance);
  slice.seconds_mesh = SecondsSince(t0);
  slice.mesh = std::move(meshed.mesh);
  slice.refine_max_bracket = meshed.max_bracket;
  slice.stats = ComputeMeshStatistics(slice.mesh);
  return slice;
}

}  // namespace robossis::geometry
