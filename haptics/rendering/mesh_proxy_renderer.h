#pragma once
// "mesh-proxy": a 6-DOF god-object driven by the precomputed boundary meshes and the geometry module's FCL-tree
// signed query, with the exact IK as the final check (haptics/README.md, "Mesh walls fit to drive hardware").
//
// Each tick the proxy X_P (always feasible) follows the HC pose, translation first (at the proxy's orientation)
// then orientation (at the proxy's new position) — the two slice families coupled at the proxy's pose:
//  * HC pose feasible (exact IK): the proxy is the HC (free space; a stale or wrong mesh cannot make a wall).
//  * HC outside: the mesh gives the exact nearest point on its triangles and so the direction back inside (the
//    god-object's constraint direction, Zilles–Salisbury / Ruspini); along that line from the HC the exact IK
//    (bisection on IsPoseFeasible) finds the TRUE boundary, and the proxy is put there. In rotation the mesh lives
//    in RPY space: its outward normal n is a covector there, so the direction in world rotation vectors is
//    −E(rpy)⁻ᵀ·n (E: RPY rates → angular velocity), which is the steepest way back in the rotation metric.
//  * No slice, a failed query or no feasible point along the line: the proxy bisects from its own pose toward the
//    HC (stops at the contact; bounded, always feasible).
// The slices are those of a geometry::LiveBoundary regenerated around the PROXY pose off the real-time thread (the
// proxy moves only as fast as it slides along the wall, so its slices are less stale than slices at the HC pose),
// the atlas node answering until a live slice lands or when it is nearer to the proxy pose. Because the depth and
// the contact point come from the IK, a slice switch changes only the direction estimate by the two slices'
// disagreement, never the wall's position: the switch is not felt as a step.
//
// Wrench: the virtual coupling of the proxy method, F = k_f·(p_P − p_HC) − w_f·c_f·v, τ = k_τ·log(R_P·R_HCᵀ) −
// w_τ·c_τ·ω (eq. 18–19 with d = proxy offset): zero at the true boundary, growing continuously, no moving average.
// w = min(1, depth / damping_fade) in contact and 0 in free space (w = 1 everywhere with damping_fade = 0: the
// paper's law). ContactDampingWeight below. With MeshProxyParams::force_rate on, the spring is that of the
// ForceRateShaper's attachment, which follows the proxy only as fast as the force may change, never actively.

#include <array>
#include <memory>

#include "geometry/boundary_atlas.h"
#include "geometry/live_boundary.h"
#include "haptics/rendering/force_rate_shaper.h"
#include "haptics/rendering/haptic_types.h"
#include "haptics/rendering/wall_law.h"
#include "robot/rsr_kinematics.h"

namespace robossis::haptics {

struct MeshProxyParams {
  int bisection_steps = 14;  // [assumed] as the proxy: bracket / 2^14 per bisection
  // [assumed] When the mesh's nearest point is not feasible (a face cuts outside the true region by its chord
  // error, or the slice is stale), the search along the line goes this much further per try, doubling, up to
  // `search_expansions` tries: 0.5 mm / 0.25 deg, then 1, 2, 4 ... (mesh errors are ≤ 1 mm / 0.3 deg, README).
  double search_step_m = 0.0005;
  double search_step_rad = 0.25 * 3.14159265358979323846 / 180;
  int search_expansions = 5;
  // [assumed] Optional memory of the contact (0: off). Far outside, the nearest face of a slice can change
  // abruptly (the projection has no history), so the proxy may jump; with a limit > 0 the proxy moves per tick at
  // most the HC's own motion plus this much (m, rad) toward the new contact, and catches up over a few ticks.
  double max_extra_step_m = 0;
  double max_extra_step_rad = 0;
  // [assumed] The damper of eq. 18–19 (−c_f·v, −c_τ·ω) acts only in contact, its weight growing linearly from 0 at
  // the true boundary to 1 at this depth of the proxy offset (m, rad); 0: the paper's damper everywhere (Algorithm
  // 1, lines 18–20). In free space the paper's damper is a force where there is no wall (above 1 N beyond 67 mm/s)
  // and steps with the handle's velocity (6 N when the handle at 400 mm/s meets the sigma.7's own stop); faded in
  // with depth it cannot step at the wall's onset either. Any weight in [0, 1] keeps the damper dissipative.
  double damping_fade_m = 0;
  double damping_fade_rad = 0;
  // [assumed] Memory of the translational contact direction (0: off). Far outside, the mesh's nearest face can
  // switch between ticks (two faces at nearly the same distance: the force direction flips by tens of degrees);
  // with a limit > 0 the direction of the line along which the IK finds the true boundary turns toward the mesh's
  // new nearest-point direction by at most this angle (rad) per tick. The proxy stays on the true boundary.
  double max_direction_step_rad = 0;
  // The force-rate shaper between the proxy and the displayed force (off with max_rate_n_per_s = 0): the force
  // changes by at most that rate, passively, and unloads before a fast hand leaves the wall (ForceRateShaper).
  ForceRateShaperParams force_rate;
};

// The weight of the damper at a proxy offset `depth` (m or rad): 1 with fade <= 0 (the paper's law), else
// min(1, depth / fade) (0 in free space, where the offset is 0).
inline double ContactDampingWeight(double depth, double fade) noexcept {
  if (!(fade > 0)) return 1.0;
  return depth >= fade ? 1.0 : depth / fade;
}

class MeshProxyRenderer final : public HapticRenderer {
 public:
  // `atlas` may be null when `live` is given; at least one of the two is needed. simulated_latency_s >= 0: the live
  // slices are refreshed by StepSimulatedBackground with that modelled latency; < 0: the caller runs live->Start().
  MeshProxyRenderer(const robot::RsrModel& model, const HcToRsrMap& map, const WrenchLimits& limits, double rate_hz,
                    const WallLawParams& wall, const MeshProxyParams& params,
                    std::shared_ptr<const geometry::BoundaryAtlas> atlas,
                    std::shared_ptr<geometry::LiveBoundary> live, double simulated_latency_s,
                    const char* name = "mesh-proxy");

  const char* name() const noexcept override { return name_; }
  // The god-object pose (RSR side, frame F): always feasible by the exact IK; the set-point to send the follower.
  const Eigen::Isometry3d& proxy_pose() const { return X_FP_; }
  const Eigen::Isometry3d* constrained_pose() const noexcept override { return &X_FP_; }
  void StepSimulatedBackground(double now_s) override;

  // Diagnostics of the last tick: whether each family's contact came from the mesh line search (true) or the
  // fallback bisection from the proxy (false, also in free space).
  bool last_translation_from_mesh() const { return translation_from_mesh_; }
  bool last_rotation_from_mesh() const { return rotation_from_mesh_; }
  // The weights of the damper in the last tick (force, torque): ContactDampingWeight's, or the force-rate
  // shaper's stronger damper divided by c_f. The wrench minus −w·c·v is the wall's own part (the direction metric
  // scores it).
  double last_force_damping_weight() const noexcept { return force_damping_weight_; }
  double last_torque_damping_weight() const noexcept { return torque_damping_weight_; }

 protected:
  HapticStatus Render(const RsrSideState& state, Eigen::Vector3d& f_F, Eigen::Vector3d& tau_F) noexcept override;
  void ResetMethod(const Eigen::Isometry3d& X_OH) noexcept override;

 private:
  // The slices for the proxy pose: live if nearer to it than the atlas node (either may be null).
  void SelectFields(const geometry::BoundaryDistanceField** dexterous,
                    const geometry::BoundaryDistanceField** rotational) noexcept;
  bool MoveTranslation(const Eigen::Vector3d& p_HC, const geometry::BoundaryDistanceField* field) noexcept;
  bool MoveRotation(const Eigen::Matrix3d& R_HC, const geometry::BoundaryDistanceField* field) noexcept;
  // When the HC pose (its IK this tick) will be inside the true region, at the rate its violated joint-limit margins
  // close (the force-rate shaper unloads before then); ForceRateShaper::kNever if one of them is not closing.
  double EntryTime(const robot::RsrIkResult& ik) noexcept;

  WallLawParams wall_;
  MeshProxyParams params_;
  std::shared_ptr<const geometry::BoundaryAtlas> atlas_;
  std::shared_ptr<geometry::LiveBoundary> live_;
  std::unique_ptr<geometry::SimulatedRefresher> refresher_;
  const char* name_;
  geometry::AtlasPoseQuery query_;
  geometry::PoseBoundaryResult result_;
  Eigen::Isometry3d X_FP_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d X_FM_previous_ = Eigen::Isometry3d::Identity();  // the HC pose of the previous tick
  bool translation_from_mesh_ = false;
  bool rotation_from_mesh_ = false;
  Eigen::Vector3d u_previous_ = Eigen::Vector3d::Zero();  // last tick's translational line direction (0: none)
  double force_damping_weight_ = 1;
  double torque_damping_weight_ = 1;
  ForceRateShaper shaper_;
  std::array<double, 3 * robot::kNumArms> margins_previous_{};  // the HC pose's joint-limit margins, last tick
  bool have_margins_ = false;
};

}  // namespace robossis::haptics
