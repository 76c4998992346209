#include "haptics/device/device_sim.h"

#include <cmath>
#include <stdexcept>

#include "haptics/rendering/haptic_types.h"
#include "src/core/pose.h"

namespace robossis::haptics {

SimulatedSigma7::SimulatedSigma7(const robot::Sigma7Model& model, const DeviceSimParams& device,
                                 const HandParams& hand)
    : model_(model), device_(device), hand_(hand) {
  if (!(hand.mass_kg > 0) || !(hand.inertia_kgm2 > 0) || !(device.physics_rate_hz > 0)) {
    throw std::invalid_argument("simulated sigma.7: hand mass, inertia and physics rate must be positive");
  }
}

void SimulatedSigma7::Reset(const Eigen::Isometry3d& X_OH) noexcept {
  X_OH_ = X_OH;
  v_O_.setZero();
  w_O_.setZero();
}

DeviceStepResult SimulatedSigma7::Step(double dt, const Eigen::Vector3d& f_cmd_O, const Eigen::Vector3d& tau_cmd_O,
                                       const HandTarget& target) noexcept {
  DeviceStepResult result;
  Eigen::Vector3d f = f_cmd_O, tau = tau_cmd_O;
  result.force_clamped = SaturateNorm(f, model_.geometry().max_force_n);
  result.force_clamped = SaturateNorm(tau, model_.geometry().max_torque_nm) || result.force_clamped;
  const int substeps = std::max(1, static_cast<int>(std::ceil(dt * device_.physics_rate_hz - 1e-9)));
  const double h = dt / substeps;
  for (int k = 0; k < substeps; ++k) {
    const Eigen::Vector3d f_hand = hand_.stiffness_n_per_m * (target.X_OH.translation() - X_OH_.translation()) +
                                   hand_.damping_ns_per_m * (target.v_O - v_O_);
    const Eigen::Vector3d tau_hand =
        hand_.rot_stiffness_nm_per_rad * RotationVector(target.X_OH.linear() * X_OH_.linear().transpose()) +
        hand_.rot_damping_nms_per_rad * (target.w_O - w_O_);
    v_O_ += h / hand_.mass_kg * (f_hand + f - device_.damping_ns_per_m * v_O_);
    w_O_ += h / hand_.inertia_kgm2 * (tau_hand + tau - device_.rot_damping_nms_per_rad * w_O_);
    // Mechanical limits: the handle stops at the delta workspace boundary and at the wrist stops. The work of the
    // displayed wrench is counted with the velocity that actually moved the handle (zero when a stop held it):
    // counting it before the stop credited the wall with work on a handle that did not move (0.4 J of phantom
    // "generated" energy on push-edges for pointcloud-safe, whose force held the handle against a stop).
    const Eigen::Vector3d p_new = X_OH_.translation() + h * v_O_;
    if (robot::IsInSigma7Workspace(model_, p_new, X_OH_.linear()) ||
        !robot::IsInSigma7Workspace(model_, X_OH_.translation(), X_OH_.linear())) {
      X_OH_.translation() = p_new;
    } else {
      v_O_.setZero();
      result.at_mechanical_limit = true;
    }
    result.energy_into_hand_j += f.dot(v_O_) * h;
    const Eigen::Matrix3d R_new = RotationFromVector(h * w_O_) * X_OH_.linear();
    if (robot::WristWithinRange(model_, robot::WristJointsFromRotation(R_new)) ||
        !robot::WristWithinRange(model_, robot::WristJointsFromRotation(X_OH_.linear()))) {
      X_OH_.linear() = R_new;
    } else {
      w_O_.setZero();
      result.at_mechanical_limit = true;
    }
    result.energy_into_hand_j += tau.dot(w_O_) * h;
  }
  return result;
}

}  // namespace robossis::haptics
