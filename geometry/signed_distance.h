#pragma once
// Signed penetration query against a closed boundary mesh, with FCL (design card: "workspace boundary precomputed
// as meshes, queried with FCL for penetration depth").
//
// FCL 0.7's mesh distance is unsigned (DEPENDENCIES.md), and its sphere-vs-mesh traversal (rectangle-rectangle
// bounds, a GJK solve per candidate triangle) measured ~4x slower than the search below (BENCHMARKS.md), so the
// query is done in two steps:
//   1. FCL builds the mesh's bounding-volume tree (axis-aligned boxes); a branch-and-bound search over that tree
//      with the exact point-triangle distance at the leaves finds the closest triangle;
//   2. the closest point on that triangle is exact, and the sign is taken from the angle-weighted
//      pseudonormal of the closest feature (face, edge or vertex) -- Baerentzen & Aanaes, "Signed distance
//      computation using the angle weighted pseudonormal", IEEE TVCG 11(3), 2005: for a closed, consistently
//      oriented mesh, (q - c) . n_feature > 0 exactly when q is outside.
//
// Units and frames: a BoundaryDistanceField lives in the coordinate space of its slice (workspace_slice.h):
//   - position slices (RSR dexterous, sigma.7 translation): q in metres, in the slice's frame (F for the RSR: the
//     position of the moving-ring centre P in the fixed-ring frame; O for the sigma.7);
//   - rotational slices (RSR rotational, sigma.7 wrist): q = (roll, pitch, yaw) in RADIANS of the project's RPY
//     convention R = Rz(yaw) Ry(pitch) Rx(roll). Distances are then Euclidean distances in RPY space (rad);
//     multiply by kRadToDeg for the `signed_angle_deg` of the CLI.
//
// Real-time use (haptic tick): build BoundaryDistanceField objects at start-up (or in a background thread), keep
// one SignedDistanceQuery per real-time thread, and call Query(): it allocates nothing, locks nothing, throws
// nothing (proved by tests/geometry/signed_distance_test.cc with the allocation counter).

#include <cstdint>
#include <memory>

#include <Eigen/Core>

#include "geometry/triangle_mesh.h"

namespace robossis::geometry {

enum class QueryStatus : std::uint8_t {
  kOk = 0,
  kNoField,     // null field pointer (e.g. the atlas has no slice for this pose)
  kNonFinite,   // the query point or radius is NaN/inf, or the radius is negative
  kFclFailure,  // the tree search found no closest triangle (cannot happen for a valid field; reported, not thrown)
  kOffGrid,     // the pose lies beyond the atlas grid (boundary_atlas.h, MarkOffGrid): no atlas node answers for it
};
const char* ToString(QueryStatus status);

struct SignedDistanceResult {
  QueryStatus status = QueryStatus::kNoField;
  // Signed distance from the query SPHERE's surface to the boundary, in slice units (m or rad):
  //   > 0: the whole sphere is inside the allowable region, with this clearance;
  //   < 0: penetration depth = -signed_distance (the sphere sticks out of the region by this much).
  // For radius 0 it is the signed distance of the point q.
  double signed_distance = 0;
  // Closest point on the boundary to q (slice coordinates and units).
  Eigen::Vector3d nearest = Eigen::Vector3d::Zero();
  // Unit outward normal of the boundary at `nearest` (points from the allowable region to the forbidden side).
  // It is (q - nearest)/|q - nearest| oriented outward when q is off the surface, else the feature pseudonormal.
  // A haptic wall pushes back along -normal when signed_distance < 0.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  int triangle = -1;   // index of the closest triangle in the field's mesh
  bool inside = false;  // q (the centre) is inside the region
  // Only with SignedDistanceQuery::set_inside_cutoff: q is inside, farther than the cutoff from the boundary, and
  // the nearest point was not searched for; signed_distance is then the cutoff minus the radius (a lower bound),
  // `nearest` is q, `normal` zero, `triangle` -1.
  bool beyond_inside_cutoff = false;
};

// An immutable closed mesh prepared for queries: FCL AABB tree, face normals and angle-weighted pseudonormals of
// every edge and vertex. Thread-safe to query from several threads (each with its own SignedDistanceQuery).
class BoundaryDistanceField {
 public:
  // Throws std::invalid_argument if the mesh is empty, not watertight or not consistently oriented (the sign
  // would be meaningless). An inward-oriented mesh is flipped.
  explicit BoundaryDistanceField(TriangleMesh mesh);
  // The same with the mesh's statistics already computed (ComputeMeshStatistics of this very mesh, e.g.
  // WorkspaceSlice::stats): saves recomputing them when a slice is refreshed while the hand moves.
  BoundaryDistanceField(TriangleMesh mesh, const MeshStatistics& stats);
  ~BoundaryDistanceField();
  BoundaryDistanceField(const BoundaryDistanceField&) = delete;
  BoundaryDistanceField& operator=(const BoundaryDistanceField&) = delete;

  const TriangleMesh& mesh() const { return mesh_; }
  const MeshStatistics& stats() const { return stats_; }
  // Unique per field ever constructed in this process (a freed field's address may be reused by the next one, so
  // the query's warm start identifies fields by this, not by address).
  std::uint64_t id() const { return id_; }

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  TriangleMesh mesh_;
  MeshStatistics stats_;
  std::uint64_t id_;
  std::unique_ptr<Impl> impl_;
};

// The reusable per-thread query object: holds the warm start (previous field and closest triangle).
class SignedDistanceQuery {
 public:
  SignedDistanceQuery();
  ~SignedDistanceQuery();
  SignedDistanceQuery(const SignedDistanceQuery&) = delete;
  SignedDistanceQuery& operator=(const SignedDistanceQuery&) = delete;
  SignedDistanceQuery(SignedDistanceQuery&&) noexcept;
  SignedDistanceQuery& operator=(SignedDistanceQuery&&) noexcept;

  // Signed distance of the sphere (centre q, radius >= 0, slice units) against `field` (may be null -> kNoField).
  // Fills *out and returns out->status. Allocation-free, noexcept. Consecutive queries against the same field are
  // warm-started from the previous closest triangle (exact: it only tightens the pruning bound), so a slowly
  // moving point -- the haptic tick -- is cheaper than a random one. The field must outlive its last query.
  QueryStatus Query(const BoundaryDistanceField* field, const Eigen::Vector3d& q, double radius,
                    SignedDistanceResult* out) noexcept;

  // Users that only need the boundary near q (haptic walls act outside, or within a few mm of it) can skip the
  // search deep inside: after an exact query found q0 inside at distance d0 > cutoff, every q with
  // |q - q0| <= d0 - cutoff is answered at once as inside and beyond the cutoff (it cannot be nearer or across the
  // boundary). Deep inside, the exact search is the expensive case (the ball to search holds much of the mesh:
  // ~26 us at 19 deg inside a 5k-triangle rotational slice); with a cutoff it runs once per (d0 - cutoff) of
  // motion. Default: no cutoff (always exact). cutoff <= 0 turns it off.
  void set_inside_cutoff(double cutoff) noexcept;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace robossis::geometry
