#pragma once
// Registration of tracker measurements to the robot: rigid fits of point sets, and the tracker-to-robot-base
// transform together with the marker-body-to-ring-centre offset from a calibration motion.

#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace robossis::calibration {

struct RigidFit {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();  // to ≈ X · from
  double rms_m = 0;
  double max_m = 0;
};

// Least-squares rigid transform (rotation + translation, no scale; Umeyama via Eigen::umeyama) mapping `from`
// onto `to`; needs ≥ 3 non-collinear points. Throws std::invalid_argument on size mismatch or < 3 points.
RigidFit FitRigidTransform(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to);

struct HandEyeOptions {
  // Weight of rotation residuals against position residuals in the refinement (m per rad). Assumption: 0.1 m/rad
  // makes 1° count like 1.7 mm, the ratio of the paper's error scales (0.32 mm vs 0.07°).
  double rotation_weight_m_per_rad = 0.1;
  // Below this spread of orientations (second-largest principal angle, rad) the marker offset cannot be separated
  // from the tracker transform; the method falls back to a rigid fit of positions. Assumption: 1°.
  double min_rotation_spread_rad = 0.0174533;
  int max_pairs = 4000;  // pairs used (evenly subsampled) to bound the cost on long takes
  int iterations = 8;    // Gauss-Newton refinements after the closed-form start
};

// X_FM_i · X_MB = X_FT · X_TB_i, where X_FM are commanded ring poses in the robot base F, X_TB the tracked body
// poses in the tracker frame T, X_FT the tracker in the base and X_MB the marker body in the ring frame.
struct HandEyeResult {
  Eigen::Isometry3d X_FT = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d X_MB = Eigen::Isometry3d::Identity();
  std::string method;   // "robot-world-hand-eye (Shah) + Gauss-Newton" or "rigid fit of positions"
  int pairs = 0;
  double rms_position_m = 0, max_position_m = 0;      // residuals of the predicted ring poses
  double rms_rotation_rad = 0, max_rotation_rad = 0;
  double rotation_spread_rad = 0;
};

HandEyeResult CalibrateTrackerToBase(const std::vector<Eigen::Isometry3d>& X_FM,
                                     const std::vector<Eigen::Isometry3d>& X_TB, const HandEyeOptions& options = {});

// The residual statistics (rms/max, pairs) of result's transforms on these pairs.
void ComputeRegistrationResiduals(const std::vector<Eigen::Isometry3d>& X_FM,
                                  const std::vector<Eigen::Isometry3d>& X_TB, HandEyeResult& result);

// The ring pose in F predicted from a tracked body pose.
inline Eigen::Isometry3d RingPoseFromTracked(const HandEyeResult& r, const Eigen::Isometry3d& X_TB) {
  return r.X_FT * X_TB * r.X_MB.inverse();
}

}  // namespace robossis::calibration
