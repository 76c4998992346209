#pragma once
// The follower (RSR) as the rest of the workbench sees it: joint commands in, measured joints and pose out.
// Served by the Bullet simulation, by a pulse recorder, and later by the real motor drivers.

#include <Eigen/Geometry>

#include "robot/rsr_kinematics.h"

namespace robossis::robot {

// A set-point for the actuated joints (eq. 13 order), with the velocity feed-forward of eq. 15.
struct RsrJointCommand {
  double time_s = 0;
  RsrJointVector q = RsrJointVector::Zero();
  RsrJointVector q_dot = RsrJointVector::Zero();
};

// What the follower measures.
struct RsrFollowerState {
  double time_s = 0;
  RsrJointVector q = RsrJointVector::Zero();                // actuated joints, eq. 13 order
  Eigen::Isometry3d X_FM = Eigen::Isometry3d::Identity();  // moving-ring pose (measured, or FK of q)
  RsrJointVector effort = RsrJointVector::Zero();           // rotary torques (N·m), linear forces (N)
  bool fault = false;                                       // a limit or a drive fault; the follower holds
};

// Real-time interface: both calls are allocation-free and never throw.
class Follower {
 public:
  virtual ~Follower() = default;
  virtual void Command(const RsrJointCommand& command) noexcept = 0;
  virtual RsrFollowerState State() const noexcept = 0;
};

}  // namespace robossis::robot
