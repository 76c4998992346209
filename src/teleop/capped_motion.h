#pragma once
// Motion within the follower's limits, one implementation for both units: the follower's commanded motion and the
// leader's set-points. The next velocity moves toward the wanted pose at most at the speed caps, changes by at most
// the acceleration caps per tick, and is slow enough to stop at the wanted pose (SetPointLimits: the limits the
// follower's validator judges the set-points by).

#include "robot/rsr_kinematics.h"
#include "robot/rsr_model.h"
#include "src/teleop/setpoint_validator.h"

namespace robossis::teleop {

// The twist [v; ω] (F) for the next tick of length dt, from the current `twist`, toward `remaining`: the twist
// step [Δp; Δθ] from the current pose to the wanted one (robot::TwistStepBetween). Linear and angular parts are
// limited separately. Allocation-free.
Vector6d NextCappedTwist(const Vector6d& twist, const Vector6d& remaining, const SetPointLimits& limits,
                         double dt) noexcept;

// The same within the motors' top speeds as well: `motor_rows` is the Jacobian of eq. 15 at the current pose with
// row i divided by motor i's top speed (MotorRows), so that a twist t every motor can make has |motor_rows t|_inf
// <= 1. The twist wanted toward `remaining` is shortened along its own direction until the busiest motor is at its
// top speed; the change from `twist` stays within the acceleration caps, so that while it slows down to that
// speed the motors may still be above it for a few ticks (the follower's actuator shortens those). Allocation-free.
Vector6d NextCappedTwist(const Vector6d& twist, const Vector6d& remaining, const SetPointLimits& limits, double dt,
                         const Matrix6d& motor_rows) noexcept;

// The rows of the bound above at the pose X_FM: the Jacobian of eq. 15 with row i divided by max_joint_speed[i]
// (rad/s or m/s, eq. 13 order). Zero where a speed is infinite (no bound) or the Jacobian is not finite (a
// singular pose, which the follower holds at). Allocation-free.
Matrix6d MotorRows(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM,
                   const robot::RsrJointVector& max_joint_speed) noexcept;

}  // namespace robossis::teleop
