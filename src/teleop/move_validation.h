#pragma once
// The check of a whole eq. 9 move before it starts, for every command that moves the robot by a timed move
// (`robossis move`, the panel's jogs): the same limits the follower applies to each set-point as the move runs
// (SetPointValidator), checked over the whole path at the actuation rate.

#include "haptics/transfer/timed_move.h"
#include "robot/rsr_model.h"
#include "src/teleop/setpoint_validator.h"

namespace robossis::teleop {

// The first set-point of `move`, sampled at every actuation tick (1 / actuation_rate_hz, the end pose always),
// that breaks a limit: first the exact IK of every sample (the whole path, cones included), then the move's length
// (a move that changes the pose in less than one tick is refused: kTooFast with `shorter_than_a_tick`), then the
// peak speeds of its profile (eq. 9) against limits.caps (kTooFast at mid-move), then every sample through the
// validator. `tightest` is the smallest joint-limit margin met along the path (at the failing sample on failure).
PathVerdict ValidateMove(const transfer::TimedMove& move, const robot::RsrModel& model, const SetPointLimits& limits,
                         double actuation_rate_hz);

}  // namespace robossis::teleop
