#pragma once
// The link's own sanity check of a set-point from an authenticated leader: finite, a unit quaternion, inside
// generous bounds (data/config/link.yaml). It stops garbage (NaN, 1e300) before it reaches the follower; the
// follower's workspace, speed and acceleration checks remain the real limits. Allocation-free.

#include "src/link/link_options.h"
#include "src/teleop/link_messages.h"

namespace robossis::link {

// True if the set-point is sane; otherwise false and `why` names the first failing field.
bool IsSaneSetPoint(const teleop::SetPointMessage& m, const LinkTuning& tuning, const char** why) noexcept;

}  // namespace robossis::link
