#pragma once
// The RSR set-point the motion transfer produces at 10 kHz: a pose with its velocity and acceleration.

#include <Eigen/Geometry>

#include "src/core/pose.h"

namespace robossis::transfer {

// Twists and displacements are 6-vectors [linear; angular] expressed in the RSR fixed frame F: the linear part is
// the motion of the moving-ring centre P (m), the angular part a fixed-frame rotation vector (rad). Angular
// displacements accumulate as the sum of small fixed-frame rotation increments (R_new = Exp(dphi) R_old), which is
// exact for the increments themselves and lets every filter run on a 6-vector.
struct RsrSetPoint {
  double time_s = 0;
  Eigen::Isometry3d X_FM = Eigen::Isometry3d::Identity();
  Vector6d displacement = Vector6d::Zero();  // from the start pose, [m; rad]
  Vector6d velocity = Vector6d::Zero();      // [v (m/s); omega (rad/s)], the twist of eq. 14
  Vector6d acceleration = Vector6d::Zero();  // [m/s^2; rad/s^2]
};

}  // namespace robossis::transfer
