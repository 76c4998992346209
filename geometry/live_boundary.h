#pragma once
// The boundary at the CURRENT pose: the RSR dexterous slice at the current orientation and the rotational slice at
// the current position, regenerated off the real-time thread whenever the pose has moved by more than a tolerance,
// and published to the real-time thread without locks.
//
// Why: the dexterous boundary moves ~4 mm per degree of orientation and the rotational one ~0.2 deg per mm of
// position (geometry/README.md, "Atlas error"), so a nearest-node atlas cannot hold 0.5 mm / 0.5 deg at any sensible
// size. A slice regenerated at the actual pose is only as stale as the motion during one refresh: at the clinical
// speeds (2 mm/s, 0.2 deg/s) and the measured refresh times (BENCHMARKS.md) that is a few hundredths of a mm/deg.
// The atlas stays the start-up and fallback boundary (LivePoseQuery picks whichever slice is nearer to the pose).
//
// Threads: ONE real-time thread posts poses and acquires slices (PostPose, Acquire*, LivePoseQuery); they allocate
// nothing, lock nothing, throw nothing. The slices are generated either by the class's own background thread
// (Start/Stop), by explicit RefreshNow() calls, or, in simulations, by a SimulatedRefresher that models the
// refresh latency in simulated time (deterministic runs). Publication uses a hazard pointer per slice family: a
// slice the real-time thread acquired is not freed until that thread has acquired a newer one.

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/boundary_atlas.h"
#include "geometry/signed_distance.h"
#include "geometry/workspace_slice.h"
#include "src/core/units.h"

namespace robossis::geometry {

// [paper §V] Clinical motion speeds of the fragment (the demonstration runs at 10 mm/s, 1 deg/s).
inline constexpr double kClinicalLinearSpeedMps = 0.002;
inline constexpr double kClinicalAngularSpeedRadps = 0.2 * kDegToRad;

struct LiveBoundaryOptions {
  // [assumed] Mesh resolutions of the live slices: 4 mm (≈22k triangles, mesh error p95 0.02 mm) and 2 deg
  // (≈5k triangles, p95 0.18 deg) — geometry/README.md "Accuracy"; about 0.05 s and 0.015 s to generate.
  double dexterous_resolution_m = 0.004;
  double rotational_resolution_rad = 2 * kDegToRad;
  // [assumed] Regenerate a slice when the pose coordinate it depends on moved more than this from the slice's own
  // pose: 0.01 deg moves the dexterous boundary by ≈0.04 mm, 0.25 mm moves the rotational boundary by ≈0.05 deg.
  // (A moving hand exceeds both within a refresh anyway; they only stop refreshes while it is still.)
  double orientation_tolerance_rad = 0.01 * kDegToRad;
  double position_tolerance_m = 0.00025;
  void Validate() const;  // throws std::invalid_argument naming the field
};

// One published slice: the closed boundary mesh at `fixed` (rpy in rad for a dexterous slice, position in m for a
// rotational one), ready for queries.
struct LiveSlice {
  SliceKind kind = SliceKind::kRsrDexterous;
  Eigen::Vector3d fixed = Eigen::Vector3d::Zero();
  std::unique_ptr<const BoundaryDistanceField> field;
};

class LiveBoundary {
 public:
  LiveBoundary(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, LiveBoundaryOptions options = {});
  ~LiveBoundary();  // stops the background thread
  LiveBoundary(const LiveBoundary&) = delete;
  LiveBoundary& operator=(const LiveBoundary&) = delete;

  const LiveBoundaryOptions& options() const { return options_; }

  // ---- real-time thread ----
  // Tells the refresher where the RSR is (pose of M in F). Wait-free.
  void PostPose(const Eigen::Isometry3d& X_FM) noexcept;
  // The same with the pose as position (m) and rpy (rad), when the caller has them already.
  void PostPose(const Eigen::Vector3d& p_FM, const Eigen::Vector3d& rpy) noexcept;
  // The newest slice of each family, or nullptr before the first one. The pointer stays valid until the next
  // Acquire of the same family by the same (single) real-time thread.
  const LiveSlice* AcquireDexterous() noexcept { return Acquire(0); }
  const LiveSlice* AcquireRotational() noexcept { return Acquire(1); }

  // ---- refresh side (not real-time: allocates, takes ~0.05 s per slice) ----
  // The latest posted pose as (position m, rpy rad); false if no pose was posted yet.
  bool LatestPose(Eigen::Vector3d* p_FM, Eigen::Vector3d* rpy) const noexcept;
  // Whether the last slice generated for `kind` (published, or found empty) is missing or farther than the
  // tolerance from the pose.
  bool NeedsRefresh(SliceKind kind, const Eigen::Vector3d& p_FM, const Eigen::Vector3d& rpy) const noexcept;
  // Generates the slice of `kind` at `fixed`; nullptr when that slice is empty (the pose is unreachable).
  std::unique_ptr<LiveSlice> Generate(SliceKind kind, const Eigen::Vector3d& fixed);
  // Records that the slice of `kind` at `fixed` is being generated (NeedsRefresh measures from it); Generate does it.
  void MarkGenerated(SliceKind kind, const Eigen::Vector3d& fixed);
  // Makes `slice` the published one of its family and frees the slices nobody can still be reading.
  void Publish(std::unique_ptr<LiveSlice> slice);
  // One refresh step at the latest posted pose: regenerates and publishes each family that needs it. Returns the
  // number of slices published.
  int RefreshNow();
  // The background thread: RefreshNow() in a loop, polling every `idle_poll_s` when nothing needs refreshing.
  void Start(double idle_poll_s = 0.002);
  void Stop();
  // Slices published so far (both families): for tests and reports.
  int published_count() const noexcept { return published_count_.load(); }

 private:
  const LiveSlice* Acquire(int family) noexcept;

  const robot::RsrModel rsr_;  // copies: the refresh thread may outlive the caller's models
  const robot::Sigma7Model hc_;
  LiveBoundaryOptions options_;
  // Pose mailbox: a sequence lock over (x, y, z, roll, pitch, yaw); odd sequence = being written.
  std::atomic<std::uint64_t> pose_sequence_{0};
  std::array<std::atomic<double>, 6> pose_{};
  // Per family (0 dexterous, 1 rotational): the published slice and the real-time thread's hazard pointer.
  std::array<std::atomic<const LiveSlice*>, 2> published_{};
  std::array<std::atomic<const LiveSlice*>, 2> hazard_{};
  // Refresh side only (the thread and direct calls may overlap): the slices owned, and where each family was last
  // generated (also when it came out empty, so an unreachable pose is not retried until the pose moves).
  mutable std::mutex refresh_mutex_;
  std::vector<std::unique_ptr<LiveSlice>> owned_;
  std::array<Eigen::Vector3d, 2> generated_at_{};
  std::array<bool, 2> generated_{false, false};
  std::atomic<int> published_count_{0};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// Wall-clock seconds to regenerate each family's slice at the pose X_FM (the median of `repetitions`: on a shared
// machine the slowest run measures the other jobs more than the refresh).
struct RefreshTiming {
  double dexterous_s = 0;
  double rotational_s = 0;
  double cycle_s() const { return dexterous_s + rotational_s; }
};
RefreshTiming MeasureRefreshTiming(const robot::RsrModel& rsr, const robot::Sigma7Model& hc,
                                   const LiveBoundaryOptions& options, const Eigen::Isometry3d& X_FM,
                                   int repetitions = 5);

// Worst-case pose offset of a live slice while the pose moves at the given speeds: a change made just after a
// refresh read the pose is picked up by the next one, so the slice in use can be up to two refresh cycles old, plus
// the refresh tolerance. Orientation offset in rad (dexterous slices), position offset in m (rotational slices).
struct LiveStaleness {
  double orientation_rad = 0;
  double position_m = 0;
};
LiveStaleness WorstCaseStaleness(const RefreshTiming& timing, const LiveBoundaryOptions& options,
                                 double linear_speed_mps, double angular_speed_radps);

// Real-time pose query against the live slices, falling back to the atlas: for each family the slice whose own
// pose is nearer to the current one is used (the atlas node before the first live slice arrives, or when the pose
// jumped far from the live slice's). Posts the pose to `live`. Allocation-free, noexcept; one per real-time thread.
class LivePoseQuery {
 public:
  // `atlas` may be null (live slices only).
  void Query(LiveBoundary& live, const BoundaryAtlas* atlas, const Eigen::Isometry3d& X_FM, double position_radius_m,
             double angle_radius_rad, PoseBoundaryResult* out) noexcept;
  // SignedDistanceQuery::set_inside_cutoff for both families (m, rad); not real-time.
  void SetInsideCutoff(double position_m, double angle_rad) noexcept { fields_.SetInsideCutoff(position_m, angle_rad); }

 private:
  AtlasPoseQuery fields_;  // the two per-family queries (each keeps its own warm start)
};

// A deterministic stand-in for the background thread, in simulated time: a refresh started at time t from the pose
// posted at t becomes visible at t + latency (the modelled wall-clock time of one refresh), then the next one
// starts. Call Step() between real-time ticks. (The slices are generated when they land, from the poses of t.)
class SimulatedRefresher {
 public:
  SimulatedRefresher(LiveBoundary& live, double latency_s);
  void Step(double now_s);
  void Reset();  // drops a refresh in progress (e.g. a new episode)

 private:
  struct PendingSlice {
    SliceKind kind;
    Eigen::Vector3d fixed;
  };
  LiveBoundary& live_;
  double latency_s_;
  std::vector<PendingSlice> pending_;  // the refresh in progress: generated when it lands
  double ready_at_s_ = 0;
  bool busy_ = false;
};

}  // namespace robossis::geometry
