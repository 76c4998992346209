#pragma once
// Manual jogs of the control panel (paper Fig. 13): one axis, an amount, and either the time interval or the speed
// of the move, executed as the eq. 9 timed move (haptics/transfer/timed_move.h) from the follower's current pose.
//
// Before a jog starts the panel previews it with the check `robossis move` uses (teleop::ValidateMove: the whole
// eq. 9 path at every actuation tick by the exact IK eq. 5–8, at least one tick long, its peak speeds within the
// caps, every sample through teleop::SetPointValidator); a jog that would leave the workspace or break a cap is
// refused with the reason.
// The follower checks every set-point of the move again on the same path as it runs.

#include <string>

#include <Eigen/Geometry>

#include "haptics/transfer/timed_move.h"
#include "robot/rsr_kinematics.h"
#include "robot/rsr_model.h"
#include "src/teleop/setpoint_validator.h"

namespace robossis::panel {

// The six DOF of the moving ring, in the fixed frame F: translations along x, y, z and rotations about them.
enum class JogAxis { kX, kY, kZ, kRoll, kPitch, kYaw };
const char* ToString(JogAxis axis);            // "x", "y", "z", "roll", "pitch", "yaw"
JogAxis JogAxisFromString(const std::string& name);  // throws std::invalid_argument naming the value
bool IsRotational(JogAxis axis);

enum class JogTiming { kDuration, kSpeed };

struct JogRequest {
  JogAxis axis = JogAxis::kX;
  double amount = 0;                 // m, or rad for a rotation (signed)
  JogTiming timing = JogTiming::kDuration;
  double duration_s = 1.0;           // used with kDuration
  double peak_speed = 0;             // m/s or rad/s, used with kSpeed: eq. 9's peak speed pi/2 · |dx| / dt
};

// What a jog must respect: the follower's set-point limits (follower.yaml, caps from transfer.yaml).
struct JogLimits {
  teleop::SetPointLimits setpoint;
  double actuation_rate_hz = 10000;  // transfer.yaml rates.actuation_rate_hz: the preview checks every tick
};

struct JogVerdict {
  bool accepted = false;
  std::string reason;                       // why it was refused (empty when accepted)
  Eigen::Isometry3d X_FM_start = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d X_FM_end = Eigen::Isometry3d::Identity();
  double duration_s = 0;
  double peak_speed = 0;                    // m/s or rad/s
  robot::RsrLimitCheck tightest{};          // the smallest margin met along the path
};

// The eq. 9 request of a jog (the change in F) and its duration. Throws std::invalid_argument naming the field on a
// non-finite amount, a non-positive duration or speed.
transfer::TimedMoveRequest ToTimedMoveRequest(const JogRequest& request, double start_time_s);
double JogDuration(const JogRequest& request);

// The preview: the path from X_FM_start checked by teleop::ValidateMove against the joint limits and the caps.
JogVerdict PreviewJog(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM_start, const JogRequest& request,
                      const JogLimits& limits);

}  // namespace robossis::panel
