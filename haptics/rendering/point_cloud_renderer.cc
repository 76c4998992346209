#include "haptics/rendering/point_cloud_renderer.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "robot/rsr_kinematics.h"
#include "src/core/pose.h"

namespace robossis::haptics {

std::vector<Eigen::Vector3d> FibonacciSphere(int n) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(n);
  const double golden = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = golden * i;
    points.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
  }
  return points;
}

PointCloudRenderer::PointCloudRenderer(const robot::RsrModel& model, const HcToRsrMap& map,
                                       const WrenchLimits& limits, double rate_hz, const WallLawParams& wall,
                                       const PointCloudParams& cloud, const char* name)
    : HapticRenderer(model, map, limits, rate_hz),
      wall_(wall),
      cloud_(cloud),
      name_(name),
      filter_(cloud.moving_average_window) {
  if (cloud.translation_points < 2 || cloud.rotation_points < 2 || !(cloud.translation_radius_m > 0) ||
      !(cloud.rotation_radius_rad > 0)) {
    throw std::invalid_argument("point cloud: radii must be positive and point counts >= 2 (got " +
                                std::to_string(cloud.translation_points) + " and " +
                                std::to_string(cloud.rotation_points) + " points)");
  }
  // 1e-9 relative slack: the paper's constants land on the cap exactly (0.12 N·m/deg × 2.5° = 0.3 N·m).
  decoupled_ = cloud.decouple_soft_torque_wall && torque_at_boundary_nm() < limits.max_torque_nm * (1 - 1e-9);
  for (const Eigen::Vector3d& u : FibonacciSphere(cloud.translation_points)) {
    translation_offsets_.push_back(cloud.translation_radius_m * u);
  }
  for (const Eigen::Vector3d& u : FibonacciSphere(cloud.rotation_points)) {
    rotation_offsets_.push_back(cloud.rotation_radius_rad * u);
    rotation_steps_.push_back(RotationFromVector(cloud.rotation_radius_rad * u));
  }
}

void PointCloudRenderer::ResetMethod(const Eigen::Isometry3d& X_OH) noexcept {
  R_translation_cloud_ = map_.ToRsr(X_OH).linear();
  filter_.Reset();
  last_dir_t_.setZero();
  last_dir_r_.setZero();
  d_t_.setZero();
  d_r_.setZero();
  outside_t_ = outside_r_ = 0;
}

HapticStatus PointCloudRenderer::Render(const RsrSideState& state, Eigen::Vector3d& f_F,
                                        Eigen::Vector3d& tau_F) noexcept {
  const Eigen::Vector3d p = state.X_FM.translation();
  const Eigen::Matrix3d R = state.X_FM.linear();
  HapticStatus status = HapticStatus::kFree;

  // Rotational cloud: orientations exp(ρ_j)·R_HC at the HC position. (Evaluated first: the translational cloud of a
  // soft torque wall needs to know whether it is in contact.)
  const robot::PoseFeasibilityAround around_hc(model_, state.X_FM);
  Eigen::Vector3d sum_rot_in = Eigen::Vector3d::Zero();
  int inside = 0;
  for (std::size_t j = 0; j < rotation_steps_.size(); ++j) {
    if (around_hc.Rotated(rotation_steps_[j])) {
      sum_rot_in += rotation_offsets_[j];
      ++inside;
    }
  }
  outside_r_ = static_cast<int>(rotation_steps_.size()) - inside;
  d_r_.setZero();
  if (outside_r_ > 0) {
    status = HapticStatus::kContact;
    if (inside > 0) {
      d_r_ = sum_rot_in / inside;  // eq. 20, rotational part
      const double norm = d_r_.norm();
      if (norm > 0) last_dir_r_ = d_r_ / norm;
    } else {
      Eigen::Vector3d dir = last_dir_r_;
      if (dir.squaredNorm() == 0) dir = RotationVector(model_.geometry().X_FM_home.linear() * R.transpose());
      if (dir.squaredNorm() > 0) dir.normalize();
      d_r_ = cloud_.rotation_radius_rad * dir;
      status = HapticStatus::kDeepPenetration;
    }
  }

  // Algorithm 1, lines 4–12, translational cloud: P_in offsets summed, outside points counted.
  // A soft torque wall does not hold the orientation (holds_orientation() false): the translational cloud stays at
  // the last orientation where the rotational cloud was free, so that turning the hand into a rotational limit does
  // not make the translational cloud push it sideways. Evaluated at the HC orientation, that force depends on the
  // orientation with no matching torque that depends on the position: a non-conservative field (+0.17 J of
  // quasi-static work around a 15 mm × 7° loop in (x, pitch) near the tilt limit) that the paper's stiff torque
  // wall keeps the hand away from, and a soft one does not (haptics/README.md, "Why pointcloud-safe generated
  // energy"). The converse coupling (the rotational cloud at the HC position) stays: the stiff translational wall
  // holds the position, and the soft torque it drives stores at most ~1 mJ in the hand.
  if (!decoupled_ || outside_r_ == 0) R_translation_cloud_ = R;
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = R_translation_cloud_;
  X.translation() = p;
  const robot::PoseFeasibilityAround around_cloud_centre(model_, X);
  Eigen::Vector3d sum_in = Eigen::Vector3d::Zero();
  inside = 0;
  for (const Eigen::Vector3d& offset : translation_offsets_) {
    if (around_cloud_centre.Translated(offset)) {
      sum_in += offset;
      ++inside;
    }
  }
  outside_t_ = static_cast<int>(translation_offsets_.size()) - inside;
  d_t_.setZero();
  if (outside_t_ > 0) {
    if (status == HapticStatus::kFree) status = HapticStatus::kContact;
    if (inside > 0) {
      d_t_ = sum_in / inside;  // eq. 20 (our reading: mean offset of the inside points), n̂ = d/‖d‖ (eq. 21)
      const double norm = d_t_.norm();
      if (norm > 0) last_dir_t_ = d_t_ / norm;
    } else {
      // Every point outside: eq. 20 is undefined. Bounded fallback (README).
      Eigen::Vector3d dir = last_dir_t_;
      if (dir.squaredNorm() == 0) dir = model_.geometry().X_FM_home.translation() - p;
      if (dir.squaredNorm() > 0) dir.normalize();
      d_t_ = cloud_.translation_radius_m * dir;
      status = HapticStatus::kDeepPenetration;
    }
  }

  // eq. 18–19 in contact (d ≠ 0), Algorithm 1 lines 19–20 in free space (d = 0 leaves only the damper).
  Vector6d wrench;
  wrench.head<3>() = WallForce(wall_, d_t_, state.v_F);
  wrench.tail<3>() = WallTorque(wall_, d_r_, state.w_F);
  // Algorithm 1 lines 16–17: "mean weighted" — the linearly weighted moving average of §VI-A.
  const Vector6d filtered = filter_.Filter(wrench);
  f_F = filtered.head<3>();
  tau_F = filtered.tail<3>();
  return status;
}

}  // namespace robossis::haptics
