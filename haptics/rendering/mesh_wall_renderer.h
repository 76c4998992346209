#pragma once
// Mesh walls (design card: "workspace boundary precomputed as meshes, queried with FCL for penetration depth"): the
// paper's spring-damper law (eq. 18–19), moving average and caps, driven by the geometry module's FCL signed
// penetration query against the precomputed boundary atlas (geometry/boundary_atlas.h) instead of point clouds.
//
//  * translation: the HC position against the dexterous slice of the nearest orientation grid node (metres, F);
//    when it is outside (signed distance s < 0) the inward penetration vector is d_in = s·n_out (length |s|);
//  * rotation: the HC's RPY against the rotational slice of the nearest position grid node (radians of RPY space);
//    the inward RPY increment s·n_out is mapped to a world-frame rotation vector by the RPY rate matrix
//    E(rpy) (ω = E·d(rpy)/dt for R = Rz(y)Ry(p)Rx(r)), so the torque is a physical torque;
//  * free space: the viscous term only, as in Algorithm 1;
//  * no slice at the nearest node (that whole slice is unreachable) or a failed query: kDeepPenetration with the
//    viscous term only (bounded; never NaN).
// The atlas is loaded before the loop; a query is O(log n) in the mesh size, allocation-free (geometry tests).
//
// With a live boundary (UseLiveBoundary; the "mesh-live" method) the slices regenerated at the current pose
// (geometry/live_boundary.h) take over from the atlas nodes whenever they are nearer to the pose: the walls are then
// as accurate as one refresh is stale, instead of one atlas grid step.

#include <memory>

#include "geometry/boundary_atlas.h"
#include "geometry/live_boundary.h"
#include "haptics/rendering/haptic_types.h"
#include "haptics/rendering/wall_law.h"

namespace robossis::haptics {

// Bumpless switch between boundary slices: when the slice answering a family changes (a refresh landed), the
// penetration vector would jump by the two slices' disagreement (at the demonstration's 1 deg/s a 0.15 s refresh
// moves the dexterous boundary ~0.6 mm: a 1.2 N step at 2000 N/m). Instead the jump is taken up linearly over
// `ticks`: the rendered vector starts where the old slice left it and converges onto the new slice's.
class SliceSwitchBlend {
 public:
  void Configure(int ticks) noexcept { ticks_ = ticks > 0 ? ticks : 0; }
  void Reset() noexcept;
  // `source`: the slice that answered this tick; `in`: its penetration vector (zero when free).
  Eigen::Vector3d Apply(const void* source, const Eigen::Vector3d& in) noexcept;

 private:
  int ticks_ = 0;
  int remaining_ = 0;
  const void* source_ = nullptr;
  Eigen::Vector3d offset_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d last_ = Eigen::Vector3d::Zero();
};

class MeshWallRenderer final : public HapticRenderer {
 public:
  MeshWallRenderer(const robot::RsrModel& model, const HcToRsrMap& map, const WrenchLimits& limits, double rate_hz,
                   const WallLawParams& wall, int moving_average_window,
                   std::shared_ptr<const geometry::BoundaryAtlas> atlas, const char* name = "mesh");

  // Live slices take over from the atlas (which may then be null). simulated_latency_s >= 0: the slices are
  // refreshed by StepSimulatedBackground with that modelled latency (simulation); < 0: the caller runs
  // live->Start() (a real loop, the refresh on its own thread). switch_blend_s: SliceSwitchBlend duration.
  void UseLiveBoundary(std::shared_ptr<geometry::LiveBoundary> live, double simulated_latency_s,
                       double switch_blend_s = 0);
  void StepSimulatedBackground(double now_s) override;

  const char* name() const noexcept override { return name_; }
  const geometry::PoseBoundaryResult& last_query() const { return result_; }

 protected:
  HapticStatus Render(const RsrSideState& state, Eigen::Vector3d& f_F, Eigen::Vector3d& tau_F) noexcept override;
  void ResetMethod(const Eigen::Isometry3d& X_OH) noexcept override;

 private:
  WallLawParams wall_;
  std::shared_ptr<const geometry::BoundaryAtlas> atlas_;
  std::shared_ptr<geometry::LiveBoundary> live_;
  std::unique_ptr<geometry::SimulatedRefresher> refresher_;
  const char* name_;
  WeightedMovingAverage filter_;
  geometry::AtlasPoseQuery query_;
  geometry::LivePoseQuery live_query_;
  SliceSwitchBlend translation_blend_, rotation_blend_;
  geometry::PoseBoundaryResult result_;
};

// ω = E(rpy) · d(rpy)/dt for R = Rz(yaw) Ry(pitch) Rx(roll) (world-frame angular velocity).
Eigen::Matrix3d RpyRateToAngularVelocity(const Eigen::Vector3d& rpy) noexcept;

}  // namespace robossis::haptics
