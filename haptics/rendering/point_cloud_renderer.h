#pragma once
// The paper's method (§VI-A, Algorithm 1, eq. 18–21): two spherical point clouds around the HC pose, every point
// checked with the RSR feasibility test (robot::IsPoseFeasible: the IK of eq. 5–8 against the joint limits), the
// penetration vector from the points that remain inside, the spring-damper law, a linearly weighted moving average
// (window 5, newest heaviest) and the 15 N / 0.3 N·m caps; viscous force only in free space.
//
// Our reading of what the paper leaves open (also in haptics/README.md):
//  * The clouds. The translational cloud is n_t points on the surface of a sphere of radius 15 mm around the HC
//    position, at the HC orientation; the rotational cloud is n_r orientations at 5° from the HC orientation, written
//    as world-frame rotation vectors (R_j = exp(ρ_j)·R_HC), at the HC position. Algorithm 1 adds PC(N) to X(t)_HC;
//    for the small angles involved a rotation vector equals an RPY increment to first order, and it makes the
//    resulting torque a physical torque vector. Points lie on the sphere's surface (Fibonacci lattice): then a
//    pose on the boundary has half its cloud inside, whose mean offset is r/2, so the spring gives exactly
//    k_f·7.5 mm = 15 N and k_τ·2.5° = 0.3 N·m there: "the force … increases to a maximum (15 N and 0.3 Nm) at the
//    edge of the boundary" (§VI-B, Fig. 11).
//  * eq. 20, "the mean of the point clouds remaining inside": the mean of the OFFSETS (P_in − X_HC) of the inside
//    points, divided by the number of inside points (not by the total n). Its length grows monotonically from 0
//    (cloud fully inside) to the cloud radius (one point left inside) as the HC moves out.
//  * eq. 18–19 sign: that mean offset d points from the HC into the allowed region, and n̂ = d/‖d‖ (eq. 21). Taken
//    literally, −‖d‖·n̂·k_f pushes the hand OUT of the workspace; we apply +k_f·d so the wall pushes back inside
//    (what Fig. 11–12 show). The damper −c·v is kept in contact and in free space (Algorithm 1 lines 19–20).
//  * All points outside (the HC is more than a radius beyond the boundary): eq. 20 is undefined (no point inside).
//    We keep the last inward direction at full depth (radius), else the direction back to the RSR home pose, and
//    report kDeepPenetration. The force stays bounded by the caps.
//  * The moving average runs on every tick (contact and free), so entering and leaving contact are filtered alike.
//  * A soft torque wall (ours, not the paper's: k_τ·r_rot/2 below the torque cap, the device-safe preset) cannot hold
//    the hand's orientation; the translational cloud is then evaluated at the last orientation where the rotational
//    cloud was free instead of at the HC orientation (holds_orientation(); haptics/README.md).

#include <vector>

#include "haptics/rendering/haptic_types.h"
#include "haptics/rendering/wall_law.h"

namespace robossis::haptics {

struct PointCloudParams {
  double translation_radius_m = 0.015;                          // [paper] 15 mm
  double rotation_radius_rad = 5.0 * 3.14159265358979323846 / 180;  // [paper] 5°
  int translation_points = 200;                                 // [assumed] configurable
  int rotation_points = 200;                                    // [assumed] configurable
  int moving_average_window = 5;                                // [paper]
  // [assumed, ours] For a soft torque wall, evaluate the translational cloud at the last orientation where the
  // rotational cloud was free (PointCloudRenderer::holds_orientation()). No effect with the paper's constants.
  bool decouple_soft_torque_wall = true;
};

// n unit vectors spread evenly on the sphere (Fibonacci lattice). Setup-time helper.
std::vector<Eigen::Vector3d> FibonacciSphere(int n);

class PointCloudRenderer final : public HapticRenderer {
 public:
  PointCloudRenderer(const robot::RsrModel& model, const HcToRsrMap& map, const WrenchLimits& limits, double rate_hz,
                     const WallLawParams& wall, const PointCloudParams& cloud, const char* name = "pointcloud");

  const char* name() const noexcept override { return name_; }

  // Diagnostics of the last tick.
  int translation_points_outside() const { return outside_t_; }
  int rotation_points_outside() const { return outside_r_; }
  const Eigen::Vector3d& last_penetration_translation() const { return d_t_; }
  const Eigen::Vector3d& last_penetration_rotation() const { return d_r_; }
  // The torque of the rotational spring at the boundary, where half the cloud is inside (depth r_rot/2).
  double torque_at_boundary_nm() const { return wall_.k_tau_nm_per_rad * 0.5 * cloud_.rotation_radius_rad; }
  // False for a soft torque wall (torque_at_boundary_nm() below the torque cap: the device-safe preset), when
  // decouple_soft_torque_wall is set. Such a wall cannot hold the hand's orientation, and the translational cloud is
  // then evaluated at the last orientation where the rotational cloud was free, not at the HC orientation.
  bool holds_orientation() const { return !decoupled_; }

 protected:
  HapticStatus Render(const RsrSideState& state, Eigen::Vector3d& f_F, Eigen::Vector3d& tau_F) noexcept override;
  void ResetMethod(const Eigen::Isometry3d& X_OH) noexcept override;

 private:
  WallLawParams wall_;
  PointCloudParams cloud_;
  const char* name_;
  std::vector<Eigen::Vector3d> translation_offsets_;  // radius · unit, sized once
  std::vector<Eigen::Vector3d> rotation_offsets_;     // rotation vectors ρ_j
  std::vector<Eigen::Matrix3d> rotation_steps_;       // exp(ρ_j), precomputed
  WeightedMovingAverage filter_;
  Eigen::Vector3d last_dir_t_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d last_dir_r_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d d_t_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d d_r_ = Eigen::Vector3d::Zero();
  int outside_t_ = 0, outside_r_ = 0;
  bool decoupled_ = false;
  Eigen::Matrix3d R_translation_cloud_ = Eigen::Matrix3d::Identity();  // orientation of the translational cloud
};

}  // namespace robossis::haptics
