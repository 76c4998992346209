#include "src/panel/jog.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "src/core/units.h"
#include "src/teleop/move_validation.h"

namespace robossis::panel {
namespace {

constexpr const char* kAxisNames[] = {"x", "y", "z", "roll", "pitch", "yaw"};

std::string DescribeLimit(const robot::RsrLimitCheck& check) {
  const bool angular = check.joint != robot::RsrJointKind::kStroke;
  const double scale = angular ? kRadToDeg : kMToMm;
  const char* unit = angular ? "deg" : "mm";
  char text[200];
  std::snprintf(text, sizeof text, "arm %d %s %.2f %s, limit %.2f %s (margin %.2f %s)", check.arm + 1,
                robot::ToString(check.joint), check.value * scale, unit, check.limit * scale, unit,
                check.margin * scale, unit);
  return text;
}

}  // namespace

const char* ToString(JogAxis axis) { return kAxisNames[static_cast<int>(axis)]; }

JogAxis JogAxisFromString(const std::string& name) {
  for (int i = 0; i < 6; ++i)
    if (name == kAxisNames[i]) return static_cast<JogAxis>(i);
  throw std::invalid_argument("jog axis: '" + name + "' is not one of x, y, z, roll, pitch, yaw");
}

bool IsRotational(JogAxis axis) { return static_cast<int>(axis) >= 3; }

double JogDuration(const JogRequest& request) {
  if (!std::isfinite(request.amount)) throw std::invalid_argument("jog amount: expected a finite number");
  if (request.timing == JogTiming::kDuration) {
    if (!(request.duration_s > 0) || !std::isfinite(request.duration_s))
      throw std::invalid_argument("jog duration: expected a positive number of seconds");
    return request.duration_s;
  }
  if (!(request.peak_speed > 0) || !std::isfinite(request.peak_speed))
    throw std::invalid_argument("jog speed: expected a positive speed");
  // eq. 9 peaks at pi/2 · |dx| / dt, so the interval for a given peak speed is pi/2 · |dx| / v.
  return transfer::TimedMove::DurationForPeakSpeeds(ToTimedMoveRequest(request, 0), request.peak_speed,
                                                    request.peak_speed);
}

transfer::TimedMoveRequest ToTimedMoveRequest(const JogRequest& request, double start_time_s) {
  if (!std::isfinite(request.amount)) throw std::invalid_argument("jog amount: expected a finite number");
  transfer::TimedMoveRequest move;
  const int axis = static_cast<int>(request.axis);
  if (IsRotational(request.axis))
    move.delta_rot_F[axis - 3] = request.amount;  // about the fixed-frame axis
  else
    move.delta_p_F[axis] = request.amount;
  move.start_time_s = start_time_s;
  return move;
}

JogVerdict PreviewJog(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM_start, const JogRequest& request,
                      const JogLimits& limits) {
  JogVerdict verdict;
  verdict.X_FM_start = X_FM_start;
  verdict.X_FM_end = X_FM_start;
  double duration_s = 0;
  try {
    duration_s = request.amount == 0 ? 0 : JogDuration(request);
  } catch (const std::invalid_argument& e) {
    verdict.reason = e.what();
    return verdict;
  }
  const transfer::TimedMove move(X_FM_start, ToTimedMoveRequest(request, 0), duration_s);  // eq. 9
  verdict.duration_s = duration_s;
  verdict.X_FM_end = move.X_FM_end();
  const bool rotational = IsRotational(request.axis);
  verdict.peak_speed = rotational ? move.peak_angular_speed_rad_s() : move.peak_linear_speed_m_s();
  const teleop::PathVerdict check = teleop::ValidateMove(move, model, limits.setpoint, limits.actuation_rate_hz);
  verdict.tightest = check.tightest;
  if (!check.ok()) {
    char text[200];
    const double scale = rotational ? kRadToDeg : kMToMm;
    const char* unit = rotational ? "deg/s" : "mm/s";
    if (check.verdict == teleop::SetPointVerdict::kInfeasible) {
      std::snprintf(text, sizeof text, "the move leaves the workspace at %.0f %% of its path: ",
                    duration_s > 0 ? 100.0 * check.time_s / duration_s : 100.0);
      verdict.reason = text + DescribeLimit(check.tightest);
    } else if (check.shorter_than_a_tick) {
      std::snprintf(text, sizeof text, "the move lasts %.3g s, less than one actuation tick (%.3g s): lengthen the "
                    "time interval", duration_s, 1.0 / limits.actuation_rate_hz);
      verdict.reason = text;
    } else if (check.verdict == teleop::SetPointVerdict::kTooFast) {
      const double cap = rotational ? limits.setpoint.caps.max_angular_speed_rad_s
                                    : limits.setpoint.caps.max_linear_speed_m_s;
      std::snprintf(text, sizeof text, "peak speed %.3f %s exceeds the cap %.3f %s: lengthen the time interval",
                    verdict.peak_speed * scale, unit, cap * scale, unit);
      verdict.reason = text;
    } else {
      verdict.reason = std::string("the move's set-points are refused: ") + teleop::ToString(check.verdict);
    }
    return verdict;
  }
  verdict.accepted = true;
  return verdict;
}

}  // namespace robossis::panel
