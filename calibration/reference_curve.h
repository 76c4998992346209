#pragma once
// The reference (commanded) trajectory as a continuous-time curve with its velocity, for the clock fit: the fit
// moves the tracker's frames along the reference's time axis by fractions of a sample, so it needs the pose and
// its rate of change between samples, not the nearest sample.

#include <Eigen/Geometry>

#include "calibration/trajectory.h"

namespace robossis::calibration {

struct ReferenceState {
  Eigen::Vector3d p_FM;      // ring position (m)
  Eigen::Matrix3d R_FM;      // ring orientation
  Eigen::Vector3d v_FM;      // ring velocity (m/s)
  Eigen::Vector3d w_FM;      // angular velocity in F (rad/s): R(t + dt) ≈ exp(w dt) R(t)
};

// Position: cubic Hermite between samples with finite-difference (Catmull-Rom, non-uniform) tangents, so position
// and velocity are continuous. Orientation: slerp between samples (as InterpolatePose); its angular velocity is the
// node rates (the same finite differences) interpolated linearly, continuous as well. At the two end samples the
// tangents are one-sided.
class ReferenceCurve {
 public:
  explicit ReferenceCurve(const PoseTrajectory& trajectory);
  // False when t is outside [t_front, t_back].
  bool Evaluate(double t, ReferenceState& state) const;
  // The linear interpolation's position at t (InterpolatePose), to bound what the choice of interpolation costs.
  bool LinearPosition(double t, Eigen::Vector3d& p) const;
  double t_front() const { return trajectory_.t_s.front(); }
  double t_back() const { return trajectory_.t_s.back(); }

 private:
  const PoseTrajectory& trajectory_;
  std::vector<Eigen::Vector3d> v_, w_;  // node velocity and angular velocity
};

}  // namespace robossis::calibration
