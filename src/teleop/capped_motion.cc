#include "src/teleop/capped_motion.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace robossis::teleop {

namespace {

constexpr double kNoBound = std::numeric_limits<double>::infinity();

// The largest speed from which a motion decelerating at `accel` (one change of accel*dt per tick) still stops
// within `distance`: the discrete form of v^2 / (2 a) + v dt / 2 = d.
double BrakingSpeed(double distance, double accel, double dt) noexcept {
  const double h = 0.5 * accel * dt;
  return std::max(0.0, -h + std::sqrt(h * h + 2.0 * accel * distance));
}

// One part (linear or angular) of the velocity wanted: towards `step`, at most `speed`, and slow enough to stop
// there at `accel`.
Eigen::Vector3d WantedVelocity(const Eigen::Vector3d& step, double speed, double accel, double dt) noexcept {
  const double d = step.norm();
  if (!(d > 0 && dt > 0)) return Eigen::Vector3d::Zero();
  return step * (std::min({speed, d / dt, BrakingSpeed(d, accel, dt)}) / d);
}

// One part of the next velocity: from `v` toward `wanted`, changed by at most accel*dt.
Eigen::Vector3d Accelerated(const Eigen::Vector3d& v, const Eigen::Vector3d& wanted, double accel,
                            double dt) noexcept {
  Eigen::Vector3d change = wanted - v;
  const double n = change.norm(), max_change = accel * dt;
  if (n > max_change) change *= max_change / n;
  return v + change;
}

Vector6d WantedTwist(const Vector6d& remaining, const SetPointLimits& limits, double dt) noexcept {
  Vector6d wanted;
  wanted.head<3>() =
      WantedVelocity(remaining.head<3>(), limits.caps.max_linear_speed_m_s, limits.max_linear_accel_m_s2, dt);
  wanted.tail<3>() =
      WantedVelocity(remaining.tail<3>(), limits.caps.max_angular_speed_rad_s, limits.max_angular_accel_rad_s2, dt);
  return wanted;
}

Vector6d AcceleratedTwist(const Vector6d& twist, const Vector6d& wanted, const SetPointLimits& limits,
                          double dt) noexcept {
  Vector6d next;
  next.head<3>() = Accelerated(twist.head<3>(), wanted.head<3>(), limits.max_linear_accel_m_s2, dt);
  next.tail<3>() = Accelerated(twist.tail<3>(), wanted.tail<3>(), limits.max_angular_accel_rad_s2, dt);
  return next;
}

}  // namespace

Vector6d NextCappedTwist(const Vector6d& twist, const Vector6d& remaining, const SetPointLimits& limits,
                         double dt) noexcept {
  return AcceleratedTwist(twist, WantedTwist(remaining, limits, dt), limits, dt);
}

Vector6d NextCappedTwist(const Vector6d& twist, const Vector6d& remaining, const SetPointLimits& limits, double dt,
                         const Matrix6d& motor_rows) noexcept {
  Vector6d wanted = WantedTwist(remaining, limits, dt);
  const double busiest = (motor_rows * wanted).lpNorm<Eigen::Infinity>();  // the busiest motor's share of its top
  if (busiest > 1) wanted /= busiest;
  return AcceleratedTwist(twist, wanted, limits, dt);
}

Matrix6d MotorRows(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM,
                   const robot::RsrJointVector& max_joint_speed) noexcept {
  if (!(max_joint_speed.array() < kNoBound).any()) return Matrix6d::Zero();  // no Jacobian to compute
  const Matrix6d J = robot::CalcJacobian(model, X_FM);  // eq. 15
  if (!J.allFinite()) return Matrix6d::Zero();
  Matrix6d rows;
  for (int i = 0; i < 6; ++i) rows.row(i) = J.row(i) / max_joint_speed[i];  // 0 where the speed is infinite
  return rows;
}

}  // namespace robossis::teleop
