#pragma once
// The boundary atlas: a family of precomputed boundary meshes over the pose coordinates a slice depends on,
//   - RSR dexterous slices over a regular grid of orientations (roll, pitch, yaw of R_FM),
//   - RSR rotational slices over a regular grid of positions (p_FM),
// saved as a folder, loaded at start-up, and looked up for the current pose by the nearest grid node (O(1)).
//
// Folder layout (documented in geometry/README.md):
//   DIR/manifest.json              format, units, grids, resolutions, the fingerprint of the robot and device
//                                  geometry and limits it was built for, and per slice: node, file, bytes, FNV-1a
//                                  (64-bit, standard offset basis) hash, volume, triangles; written LAST
//   DIR/dexterous/d_I_J_K.ply      binary PLY, millimetres (position of P in F)
//   DIR/rotational/r_I_J_K.ply     binary PLY, degrees (roll, pitch, yaw)
// An atlas is built in a staging folder and moved into place whole (StagedOutputDir); Load() checks every file's
// size and hash against the manifest, so a partial or corrupt atlas never loads (it throws, naming the file).
// Grid nodes where the slice is empty (the pose is unreachable everywhere) have no file and no slice; the manifest
// still lists them ("empty": true), so it names every node of its grids and Load() refuses one that does not.

#include <array>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/signed_distance.h"
#include "geometry/workspace_slice.h"
#include "src/core/units.h"

namespace robossis::geometry {

// How far beyond the end nodes of its grid an atlas answers, per axis: half a step, but never more than these
// (assumptions, not in the paper). The nearest-node error grows by about 1 mm per degree of orientation and 0.2 deg
// per mm of position (README "Boundary error"), so a node farther than 5 deg / 15 mm is off by several mm / deg;
// without the cap a coarse grid (or a one-node axis, whose step means nothing) would claim to cover far poses.
inline constexpr double kMaxCoverageHalfStepRad = 5.0 * robossis::kDegToRad;
inline constexpr double kMaxCoverageHalfStepM = 0.015;

// One axis of a regular grid: count nodes at min + step * i (SI units: rad or m).
struct GridAxis {
  double min = 0;
  double step = 0;
  int count = 1;
  double max() const { return min + step * (count - 1); }
  int Nearest(double x) const noexcept;  // clamped to [0, count - 1]
};

struct AtlasSpec {
  // Dexterous slices: a grid over (roll, pitch, yaw) of R_FM (rad); mesh resolution in m.
  std::array<GridAxis, 3> orientation_grid{};
  double dexterous_resolution_m = 0.004;
  // Rotational slices: a grid over p_FM (m); mesh resolution in rad.
  std::array<GridAxis, 3> position_grid{};
  double rotational_resolution_rad = 0.0349;

  // The defaults (assumptions; see README "Atlas defaults"): orientation grid roll, pitch -20..20 deg step 5 deg,
  // yaw -40..40 deg step 10 deg, meshes at 6 mm; positions x, y -120..120 mm step 30 mm, z home-60..home+60 mm
  // step 20 mm, meshes at 3 deg.
  static AtlasSpec Default(const robot::RsrModel& rsr);
  // A small atlas (a few seconds to build) for the test suite and `demo --fast`.
  static AtlasSpec Coarse(const robot::RsrModel& rsr);
  void Validate() const;  // throws std::invalid_argument naming the field
};

struct AtlasSlice {
  SliceKind kind = SliceKind::kRsrDexterous;
  Eigen::Vector3i node = Eigen::Vector3i::Zero();        // grid indices
  Eigen::Vector3d fixed = Eigen::Vector3d::Zero();       // rpy (rad) or position (m) of the node
  std::shared_ptr<const BoundaryDistanceField> field;    // mesh in slice SI units
};

class BoundaryAtlas {
 public:
  // Loads DIR (see the layout above). Throws std::runtime_error naming the file and the problem.
  static BoundaryAtlas Load(const std::filesystem::path& dir);

  // Throws std::runtime_error naming `where` unless the atlas was built for exactly this geometry and these limits
  // (an atlas of another robot, or of other limits, answers with the wrong boundary).
  void RequireBuiltFor(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, const std::string& where) const;
  const std::string& fingerprint() const { return fingerprint_; }
  void set_fingerprint(std::string fingerprint) { fingerprint_ = std::move(fingerprint); }

  // Whether rpy / p_FM lies on the grid or within its margin past the end nodes on every axis: half a step, at
  // most kMaxCoverageHalfStepRad / kMaxCoverageHalfStepM (a one-node axis: the cap). Beyond that the pose is off
  // the grid and the nearest node's slice is not an answer for it.
  bool CoversOrientation(const Eigen::Vector3d& rpy_rad) const noexcept;
  bool CoversPosition(const Eigen::Vector3d& p_FM_m) const noexcept;

  const AtlasSpec& spec() const { return spec_; }
  const std::vector<AtlasSlice>& dexterous() const { return dexterous_; }
  const std::vector<AtlasSlice>& rotational() const { return rotational_; }

  // The dexterous slice at the orientation grid node nearest to rpy (rad); nullptr if that node's slice is empty.
  // O(1), allocation-free, noexcept.
  const AtlasSlice* FindDexterous(const Eigen::Vector3d& rpy_rad) const noexcept;
  // The rotational slice at the position grid node nearest to p_FM (m); nullptr if empty. O(1), noexcept.
  const AtlasSlice* FindRotational(const Eigen::Vector3d& p_FM_m) const noexcept;

  // Assembles an atlas from slices in memory (used by BuildAtlas and the tests).
  BoundaryAtlas(AtlasSpec spec, std::vector<AtlasSlice> dexterous, std::vector<AtlasSlice> rotational);
  BoundaryAtlas() = default;

 private:
  AtlasSpec spec_;
  std::string fingerprint_;
  std::vector<AtlasSlice> dexterous_, rotational_;
  std::vector<int> dexterous_index_, rotational_index_;  // grid node -> slice index or -1
};

// FNV-1a 64-bit hash (offset basis 14695981039346656037, prime 1099511628211) as 16 hex digits.
std::string Fnv1a64Hex(const std::string& bytes);

// A hash of every number of the RSR and sigma.7 geometry and limits an atlas depends on.
std::string GeometryFingerprint(const robot::RsrModel& rsr, const robot::Sigma7Model& hc);

// Progress of a long build: done of total slices.
using AtlasProgress = std::function<void(int done, int total)>;

// Generates every slice of `spec` and writes the atlas folder atomically to `dir` (replacing an older atlas only
// once the new one is complete). Returns the loaded atlas.
BoundaryAtlas BuildAtlas(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, const AtlasSpec& spec,
                         const std::filesystem::path& dir, const AtlasProgress& progress = {});

// The same files written into `dir`, a folder the caller stages and commits (StagedOutputDir::staging()), so a
// command can add its own files (atlas_error.json) and move the whole atlas into place only once everything
// succeeded. `dir` is not replaced or cleaned: it must be new or empty.
BoundaryAtlas BuildAtlasIn(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, const AtlasSpec& spec,
                           const std::filesystem::path& dir, const AtlasProgress& progress = {});

struct LiveSlice;  // live_boundary.h

// Both queries of one RSR pose against the atlas (and, through LivePoseQuery, the live slices).
// The slice pointers borrow from the BoundaryAtlas / LiveBoundary that was queried: valid only while it lives.
struct PoseBoundaryResult {
  // Position of P in F against the dexterous slice of the nearest orientation node: metres, frame F.
  SignedDistanceResult translation;
  // RPY of R_FM against the rotational slice of the nearest position node: radians of RPY space.
  SignedDistanceResult rotation;
  const AtlasSlice* dexterous_slice = nullptr;
  const AtlasSlice* rotational_slice = nullptr;
  // Set by LivePoseQuery when the live slice (made at a pose nearer to the current one) answered instead.
  const LiveSlice* live_dexterous_slice = nullptr;
  const LiveSlice* live_rotational_slice = nullptr;
};

// Sets the status of each family of `r` that the atlas answered (no live slice did) to kOffGrid when `atlas` does
// not cover the pose (CoversOrientation / CoversPosition); a null atlas marks nothing. Allocation-free, noexcept.
void MarkOffGrid(const BoundaryAtlas* atlas, const Eigen::Isometry3d& X_FM, PoseBoundaryResult* r) noexcept;

// Real-time pose query: one per thread. Allocation-free and noexcept.
class AtlasPoseQuery {
 public:
  // position_radius_m / angle_radius_rad: radius of the query sphere (0 for a point).
  void Query(const BoundaryAtlas& atlas, const Eigen::Isometry3d& X_FM, double position_radius_m,
             double angle_radius_rad, PoseBoundaryResult* out) noexcept;
  // The two queries against given fields (null: kNoField) at the pose (p_FM, rpy); fills out->translation and
  // out->rotation only.
  void QueryFields(const BoundaryDistanceField* translation_field, const BoundaryDistanceField* rotation_field,
                   const Eigen::Vector3d& p_FM, const Eigen::Vector3d& rpy, double position_radius_m,
                   double angle_radius_rad, PoseBoundaryResult* out) noexcept;
  // SignedDistanceQuery::set_inside_cutoff for both families (m, rad); not real-time.
  void SetInsideCutoff(double position_m, double angle_rad) noexcept {
    translation_query_.set_inside_cutoff(position_m);
    rotation_query_.set_inside_cutoff(angle_rad);
  }

 private:
  // One query object per family, so each keeps its own warm start (signed_distance.h).
  SignedDistanceQuery translation_query_;
  SignedDistanceQuery rotation_query_;
};

}  // namespace robossis::geometry
