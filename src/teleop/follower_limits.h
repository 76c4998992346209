#pragma once
// The set-point limits a follower validates against, as it publishes them with its status (FollowerLimits), and
// the leader's start-up check of its own copy against them: on two machines each reads its own data folder, and a
// leader whose caps differ from the follower's would have every set-point refused (too accelerating, too fast) or
// would be checked against another robot's workspace. The check refuses to start, naming both values.

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <string>

#include "src/teleop/follower_config.h"
#include "src/teleop/link.h"

namespace robossis::teleop {

// A fingerprint of the robot's config: the workspace/model the follower's exact IK checks set-points against
// (rsr.yaml) and the drives whose top speeds the leader's set-points keep within (actuation.yaml). FNV-1a (64 bit)
// of the bytes of `files` in order. Equal files give equal fingerprints on every machine. Throws
// std::runtime_error naming the file when one cannot be read.
std::uint64_t ModelFingerprint(std::initializer_list<std::filesystem::path> files);

// The limits of `config` as the follower publishes them.
FollowerLimits LimitsOf(const FollowerConfig& config);

// "" if `follower` (published) equals `leader` (this machine's copy) exactly, else one line naming the first field
// that differs with both values.
std::string CompareLimits(const FollowerLimits& leader, const FollowerLimits& follower);

// [assumed] How long the leader waits at start-up for a follower status carrying the limits: the follower publishes
// at 1 kHz, so a second without one means no follower is talking.
inline constexpr double kFollowerLimitsWait_s = 1.0;

// Takes follower statuses from `link` until one carrying limits arrives (at most wait_s, polling) and compares its
// limits with `expected`. Throws std::runtime_error: none heard, or the one-line difference. Not real-time (start-up).
void CheckFollowerLimits(LeaderLink& link, const FollowerLimits& expected, double wait_s = kFollowerLimitsWait_s);

}  // namespace robossis::teleop
