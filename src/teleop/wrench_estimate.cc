#include "src/teleop/wrench_estimate.h"

#include "robot/sim/scenario.h"

namespace robossis::teleop {

Vector6d EstimateExternalWrench(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM,
                                const robot::RsrJointVector& effort, const WrenchEstimateConfig& config) noexcept {
  const Matrix6d J = robot::CalcJacobian(model, X_FM);
  Vector6d W = -(J.transpose() * effort);
  if (config.carried_mass_kg > 0) {
    const Eigen::Vector3d weight = config.carried_mass_kg * config.gravity_F_mps2;
    const Eigen::Vector3d r_F = X_FM.linear() * config.com_M;
    W.head<3>() -= weight;
    W.tail<3>() -= r_F.cross(weight);
  }
  if (config.remove_arm_weight) W -= sim::ArmGravityWrench(model, config.arm_masses, config.gravity_F_mps2, X_FM);
  if (!W.allFinite()) W.setZero();
  return W;
}

}  // namespace robossis::teleop
