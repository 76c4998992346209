#pragma once
// Workspace slices (paper §III-C, Fig. 5): 3-D sections of the 6-D pose workspace, each a region of one
// three-dimensional coordinate space with the other three pose coordinates held fixed.
//
//   kind            coordinates q (SI)                 fixed (SI)                 feasibility
//   kRsrDexterous   position p_FM of P in F (m)        orientation rpy of R_FM    robot::IsPoseFeasible
//   kRsrRotational  (roll, pitch, yaw) of R_FM (rad)   position p_FM (m)          robot::IsPoseFeasible
//   kHcTranslation  position of the delta platform in   (unused)                   delta IK within joint ranges
//                   the sigma.7 base frame O (m)
//   kHcWrist        wrist (roll, pitch, yaw) (rad)     (unused)                   robot::WristWithinRange
//
// RPY is the project's convention R = Rz(yaw) Ry(pitch) Rx(roll) (src/core/pose.h).

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/triangle_mesh.h"
#include "robot/rsr_model.h"
#include "robot/sigma7_model.h"

namespace robossis::geometry {

enum class SliceKind : std::uint8_t { kRsrDexterous, kRsrRotational, kHcTranslation, kHcWrist };
const char* ToString(SliceKind kind);                 // "rsr_dexterous", ...
SliceKind SliceKindFromString(const std::string& s);  // throws std::invalid_argument
// True for slices whose coordinates are angles (rad); false for positions (m).
bool IsAngularSlice(SliceKind kind);
// Edge-unit factor of the slice's coordinates: 1000 (m -> mm) or 180/pi (rad -> deg).
double EdgeUnitScale(SliceKind kind);
const char* EdgeUnitName(SliceKind kind);  // "mm" or "deg"

// Point-membership test of one slice: cheap, allocation-free, thread-safe (holds only const references).
class SliceFeasibility {
 public:
  SliceFeasibility(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, SliceKind kind,
                   const Eigen::Vector3d& fixed);
  bool operator()(const Eigen::Vector3d& q) const noexcept;
  SliceKind kind() const { return kind_; }
  const Eigen::Vector3d& fixed() const { return fixed_; }

 private:
  const robot::RsrModel* rsr_;
  const robot::Sigma7Model* hc_;
  SliceKind kind_;
  Eigen::Vector3d fixed_;
  Eigen::Matrix3d R_fixed_ = Eigen::Matrix3d::Identity();  // for kRsrDexterous
};

// A regular grid of sample nodes: node (i, j, k) sits at origin + spacing * (i, j, k).
struct VoxelGrid {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double spacing = 0;
  Eigen::Vector3i dims = Eigen::Vector3i::Zero();
  std::vector<std::uint8_t> feasible;  // 1 = feasible; x fastest, then y, then z

  std::size_t Index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) + static_cast<std::size_t>(dims.x()) *
                                              (static_cast<std::size_t>(j) + static_cast<std::size_t>(dims.y()) * k);
  }
  Eigen::Vector3d Node(int i, int j, int k) const { return origin + spacing * Eigen::Vector3d(i, j, k); }
};

struct SliceSpec {
  SliceKind kind = SliceKind::kRsrDexterous;
  Eigen::Vector3d fixed = Eigen::Vector3d::Zero();  // see the table above (rad or m)
  double resolution = 0.002;                        // grid spacing, m or rad (> 0)
};

struct SliceOptions {
  // Vertices are moved onto the true boundary by bisection of the feasibility along their grid edge until the
  // bracket is below this fraction of the resolution's unit: 1e-6 m (0.001 mm) or 1e-5 rad (0.0006 deg).
  double refine_tolerance_position_m = 1e-6;
  double refine_tolerance_angle_rad = 1e-5;
  // Initial search box (assumption: generous enough for the default geometry); the box grows by half its size on
  // each side, up to `max_box_growths` times, while a feasible node touches its faces.
  int max_box_growths = 4;
};

struct WorkspaceSlice {
  SliceSpec spec;
  VoxelGrid grid;
  TriangleMesh mesh;   // closed, outward oriented, vertices on the true boundary (slice SI units)
  MeshStatistics stats;
  std::size_t feasible_nodes = 0;
  std::size_t grid_evaluations = 0;  // nodes of the grid whose feasibility was tested (the others cannot be feasible)
  double refine_max_bracket = 0;  // largest final bisection bracket over all vertices (slice SI units)
  double seconds_grid = 0, seconds_mesh = 0, seconds_refine = 0;
};

// Samples the slice on a grid, extracts its closed boundary with VTK flying edges and refines every vertex onto the
// true boundary. Throws std::invalid_argument for a non-positive/non-finite resolution or fixed value, and
// std::runtime_error if the slice is empty (the fixed pose is unreachable) or unbounded within the search box.
WorkspaceSlice GenerateSlice(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, const SliceSpec& spec,
                             const SliceOptions& options = {});

// The initial search box of a slice kind (assumptions; SI units): [min, max] per coordinate.
Eigen::AlignedBox3d DefaultSearchBox(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, const SliceSpec& spec);

}  // namespace robossis::geometry
