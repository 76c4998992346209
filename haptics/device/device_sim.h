#pragma once
// A simulated sigma.7 held by a user's hand, so the closed loop human–device–wall can run without hardware.
//
// The handle and the hand move as one rigid body (mass m, rotational inertia I about the grip). The hand is an
// impedance pulling toward a scripted target pose (mass-spring-damper, [assumed] constants in haptics.yaml):
//   m·a = k_h·(p_target − p) + b_h·(v_target − v) − b_dev·v + F_display
//   I·α = k_hr·log(R_target·Rᵀ) + b_hr·(ω_target − ω) − b_dev,r·ω + τ_display
// The device limits of robot/sigma7_model.h apply: the displayed wrench is clamped to 20 N / 0.4 N·m (the
// device's peak), and the handle stops (inelastically) at the delta workspace boundary and the wrist ranges.
// Integration: semi-implicit Euler at the physics rate (several substeps per haptic tick, force held constant).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "robot/sigma7_model.h"

namespace robossis::haptics {

struct HandParams {
  double mass_kg = 0.5;
  double stiffness_n_per_m = 400;
  double damping_ns_per_m = 15;
  double inertia_kgm2 = 5e-4;
  double rot_stiffness_nm_per_rad = 2.0;
  double rot_damping_nms_per_rad = 0.03;
};

struct DeviceSimParams {
  double damping_ns_per_m = 2;
  double rot_damping_nms_per_rad = 0.001;
  double physics_rate_hz = 10000;
};

struct HandTarget {
  Eigen::Isometry3d X_OH = Eigen::Isometry3d::Identity();
  Eigen::Vector3d v_O = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_O = Eigen::Vector3d::Zero();
};

struct DeviceStepResult {
  double energy_into_hand_j = 0;  // ∫ (F_display·v + τ_display·ω) dt over the step: work of the device on the hand
  bool force_clamped = false;     // the command exceeded the device's peak force or torque
  bool at_mechanical_limit = false;
};

class SimulatedSigma7 {
 public:
  SimulatedSigma7(const robot::Sigma7Model& model, const DeviceSimParams& device, const HandParams& hand);

  void Reset(const Eigen::Isometry3d& X_OH) noexcept;  // at rest
  void set_hand(const HandParams& hand) noexcept { hand_ = hand; }

  // Advances by dt (one haptic tick) with the commanded wrench held constant.
  DeviceStepResult Step(double dt, const Eigen::Vector3d& f_cmd_O, const Eigen::Vector3d& tau_cmd_O,
                        const HandTarget& target) noexcept;

  const Eigen::Isometry3d& pose() const { return X_OH_; }
  const Eigen::Vector3d& velocity() const { return v_O_; }
  const Eigen::Vector3d& angular_velocity() const { return w_O_; }
  const robot::Sigma7Model& model() const { return model_; }

 private:
  const robot::Sigma7Model& model_;
  DeviceSimParams device_;
  HandParams hand_;
  Eigen::Isometry3d X_OH_ = Eigen::Isometry3d::Identity();
  Eigen::Vector3d v_O_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_O_ = Eigen::Vector3d::Zero();
};

}  // namespace robossis::haptics
