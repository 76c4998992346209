#pragma once
// Motion within the follower's limits, one implementation for both units: the follower's commanded motion and the
// leader's set-points. The next velocity moves toward the wanted pose at most at the speed caps, changes by at most
// the acceleration caps per tick, and is slow enough to stop at the wanted pose (SetPointLimits: the limits the
// follower's validator judges the set-points by).

#include "robot/rsr_model.h"
#include "src/teleop/setpoint_validator.h"

namespace robossis::teleop {

// The twist [v; ω] (F) for the next tick of length dt, from the current `twist`, toward `remaining`: the twist
// step [Δp; Δθ] from the current pose to the wanted one (robot::TwistStepBetween). Linear and angular parts are
// limited separately. Allocation-free.
Vector6d NextCappedTwist(const Vector6d& twist, const Vector6d& remaining, const SetPointLimits& limits,
                         double dt) noexcept;

}  // namespace robossis::teleop
