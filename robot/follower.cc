#include "robot/follower.h"

namespace robossis::robot {

const char* ToString(FollowerFault fault) {
  switch (fault) {
    case FollowerFault::kNone: return "none";
    case FollowerFault::kJointLimit: return "joint_limit";
    case FollowerFault::kDrive: return "drive";
    case FollowerFault::kFeedbackLost: return "feedback_lost";
    case FollowerFault::kFollowingError: return "following_error";
    case FollowerFault::kUnstable: return "unstable";
    case FollowerFault::kExternal: return "external";
  }
  return "unknown";
}

}  // namespace robossis::robot
