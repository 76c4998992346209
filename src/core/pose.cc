#include "src/core/pose.h"

#include <algorithm>
#include <cmath>

#include "src/core/units.h"

namespace robossis {

Eigen::Matrix3d RotationFromRpy(const Eigen::Vector3d& rpy) {
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  return R;
}

Eigen::Vector3d RpyFromRotation(const Eigen::Matrix3d& R) {
  // R(2,0) = -sin(pitch); R(2,1) = cos(pitch) sin(roll); R(2,2) = cos(pitch) cos(roll);
  // R(1,0) = cos(pitch) sin(yaw); R(0,0) = cos(pitch) cos(yaw).
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  const double c = std::hypot(R(2, 1), R(2, 2));
  if (c < 1e-12) {
    // Gimbal lock: only yaw - sign * roll is defined; choose roll = 0.
    return {0.0, pitch, std::atan2(-R(0, 1), R(1, 1))};
  }
  return {std::atan2(R(2, 1), R(2, 2)), std::atan2(-R(2, 0), c), std::atan2(R(1, 0), R(0, 0))};
}

Eigen::Isometry3d PoseFromPositionRpy(const Eigen::Vector3d& p, const Eigen::Vector3d& rpy) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = RotationFromRpy(rpy);
  X.translation() = p;
  return X;
}

Eigen::Isometry3d PoseFromMmDeg(const Vector6d& v) {
  return PoseFromPositionRpy(v.head<3>() * kMmToM, v.tail<3>() * kDegToRad);
}

Vector6d MmDegFromPose(const Eigen::Isometry3d& X) {
  Vector6d v;
  v.head<3>() = X.translation() * kMToMm;
  v.tail<3>() = RpyFromRotation(X.linear()) * kRadToDeg;
  return v;
}

double RotationAngleBetween(const Eigen::Matrix3d& R_a, const Eigen::Matrix3d& R_b) {
  return RotationVector(R_a.transpose() * R_b).norm();
}

Eigen::Vector3d RotationVector(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.axis() * aa.angle();
}

Eigen::Matrix3d RotationFromVector(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-300) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

}  // namespace robossis
