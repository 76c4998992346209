#pragma once
// Poses and orientation conventions shared by every module.
//
// Orientation is roll-pitch-yaw (the project's convention, README.md): R = Rz(yaw) · Ry(pitch) · Rx(roll), angles in radians.
// Poses are Eigen::Isometry3d named X_AB (pose of frame B in frame A), as in Drake.

#include <Eigen/Geometry>

namespace robossis {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// R = Rz(yaw) · Ry(pitch) · Rx(roll).
Eigen::Matrix3d RotationFromRpy(const Eigen::Vector3d& rpy);

// Inverse of RotationFromRpy, with pitch in [-pi/2, pi/2]. At the gimbal singularity (|pitch| = pi/2) roll is 0.
Eigen::Vector3d RpyFromRotation(const Eigen::Matrix3d& R);

// Pose from position (m) and roll-pitch-yaw (rad).
Eigen::Isometry3d PoseFromPositionRpy(const Eigen::Vector3d& p, const Eigen::Vector3d& rpy);

// Pose from the edge units: [x_mm, y_mm, z_mm, roll_deg, pitch_deg, yaw_deg].
Eigen::Isometry3d PoseFromMmDeg(const Vector6d& pose_mm_deg);

// [x_mm, y_mm, z_mm, roll_deg, pitch_deg, yaw_deg] from a pose.
Vector6d MmDegFromPose(const Eigen::Isometry3d& X);

// Rotation angle (rad, in [0, pi]) of R_a^T R_b: the geodesic distance between two orientations.
double RotationAngleBetween(const Eigen::Matrix3d& R_a, const Eigen::Matrix3d& R_b);

// Rotation vector (axis * angle) of R, angle in [0, pi].
Eigen::Vector3d RotationVector(const Eigen::Matrix3d& R);

// Rotation from a rotation vector (axis * angle).
Eigen::Matrix3d RotationFromVector(const Eigen::Vector3d& w);

}  // namespace robossis
