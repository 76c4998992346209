#include "src/teleop/capped_motion.h"

#include <algorithm>
#include <cmath>

namespace robossis::teleop {

namespace {

// The largest speed from which a motion decelerating at `accel` (one change of accel*dt per tick) still stops
// within `distance`: the discrete form of v^2 / (2 a) + v dt / 2 = d.
double BrakingSpeed(double distance, double accel, double dt) noexcept {
  const double h = 0.5 * accel * dt;
  return std::max(0.0, -h + std::sqrt(h * h + 2.0 * accel * distance));
}

// One part (linear or angular) of the next velocity: towards `step`, at most `speed`, slow enough to stop there at
// `accel`, and changed from `v` by at most accel*dt.
Eigen::Vector3d NextVelocity(const Eigen::Vector3d& v, const Eigen::Vector3d& step, double speed, double accel,
                             double dt) noexcept {
  Eigen::Vector3d wanted = Eigen::Vector3d::Zero();
  const double d = step.norm();
  if (d > 0 && dt > 0) wanted = step * (std::min({speed, d / dt, BrakingSpeed(d, accel, dt)}) / d);
  Eigen::Vector3d change = wanted - v;
  const double n = change.norm(), max_change = accel * dt;
  if (n > max_change) change *= max_change / n;
  return v + change;
}

}  // namespace

Vector6d NextCappedTwist(const Vector6d& twist, const Vector6d& remaining, const SetPointLimits& limits,
                         double dt) noexcept {
  Vector6d next;
  next.head<3>() = NextVelocity(twist.head<3>(), remaining.head<3>(), limits.caps.max_linear_speed_m_s,
                                limits.max_linear_accel_m_s2, dt);
  next.tail<3>() = NextVelocity(twist.tail<3>(), remaining.tail<3>(), limits.caps.max_angular_speed_rad_s,
                                limits.max_angular_accel_rad_s2, dt);
  return next;
}

}  // namespace robossis::teleop
