#pragma once
// The external wrench on the moving ring, estimated from the drive efforts through the statics of eq. 15: the
// actuators hold the ring against every wrench on it, J^T Q = −W (robot/rsr_kinematics.h), so the wrench on the
// ring is W = −J^T Q. What the robot needs for its own mass is removed: the weight of the ring and what it carries
// (the distal fragment in the simulation), at its centre of mass, and the arms' weight as a wrench at P
// (sim::ArmGravityWrench, virtual work). Its inertia is not removed: at the clinical speed
// caps (10 mm/s, 1 deg/s, accelerations of 5 m/s² for a few ms) it is below a newton.
//
// Where the efforts come from is the back end's: the Bullet simulation's drive forces and torques (its motors'
// applied impulses), on hardware the drive currents times the motor constants (robot::RsrFollowerState::effort of
// the back end). A force sensor between the ring and the fragment would replace this estimate (WrenchSource).
//
// Real time: noexcept, allocation-free (the Jacobian of eq. 15 and a 6x6 product).

#include <Eigen/Geometry>

#include "robot/rsr_kinematics.h"
#include "robot/rsr_model.h"
#include "robot/sim/sim_config.h"
#include "src/core/pose.h"

namespace robossis::teleop {

struct WrenchEstimateConfig {
  // The mass the ring carries and its centre (in M), and gravity in F: their weight is removed. Zero mass: nothing
  // removed. Set from the back end (the simulation knows its ring and fragment; hardware: a calibration).
  double carried_mass_kg = 0;
  Eigen::Vector3d com_M = Eigen::Vector3d::Zero();
  Eigen::Vector3d gravity_F_mps2 = Eigen::Vector3d::Zero();
  // The arms' moving masses (cylinders and pistons), whose weight the drives carry too. Unset: not removed.
  bool remove_arm_weight = false;
  sim::MassConfig arm_masses;
};

// [f at P; moment about P] on the ring from outside (the muscles, a contact), in F. Non-finite efforts or a pose
// where J is not finite give zero.
Vector6d EstimateExternalWrench(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM,
                                const robot::RsrJointVector& effort, const WrenchEstimateConfig& config) noexcept;

}  // namespace robossis::teleop
