#include "haptics/transfer/timed_move.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "src/core/units.h"

namespace robossis::transfer {

TimedMove::TimedMove(const Eigen::Isometry3d& X_FM_start, const TimedMoveRequest& request, double duration_s)
    : X_FM_start_(X_FM_start), X_FM_end_(X_FM_start), request_(request), duration_s_(duration_s) {
  if (!request.delta_p_F.allFinite() || !request.delta_rot_F.allFinite()) {
    throw std::invalid_argument("timed move: the change must be finite");
  }
  if (!std::isfinite(request.start_time_s)) throw std::invalid_argument("timed move: start time must be finite");
  const bool moves = request.delta_p_F.norm() > 0 || request.delta_rot_F.norm() > 0;
  if (!std::isfinite(duration_s) || duration_s < 0 || (moves && duration_s == 0)) {
    throw std::invalid_argument("timed move: --duration-s must be positive, got " + std::to_string(duration_s));
  }
  if (request.delta_rot_F.norm() >= kPi) {
    throw std::invalid_argument("timed move: the rotation must be below 180 deg");
  }
  // The end pose is computed once, from the start pose and the whole change, so it is exact.
  X_FM_end_.translation() = X_FM_start.translation() + request.delta_p_F;
  X_FM_end_.linear() = RotationFromVector(request.delta_rot_F) * X_FM_start.linear();
}

double TimedMove::DurationForPeakSpeeds(const TimedMoveRequest& request, double linear_speed_m_s,
                                        double angular_speed_rad_s) {
  if (!(linear_speed_m_s > 0) || !(angular_speed_rad_s > 0)) {
    throw std::invalid_argument("timed move: speeds must be positive");
  }
  // eq. 9: peak of dx/dt is dx · pi / (2 dt).
  return std::max(kPi / 2 * request.delta_p_F.norm() / linear_speed_m_s,
                  kPi / 2 * request.delta_rot_F.norm() / angular_speed_rad_s);
}

double TimedMove::peak_linear_speed_m_s() const {
  return duration_s_ > 0 ? kPi / 2 * request_.delta_p_F.norm() / duration_s_ : 0.0;
}
double TimedMove::peak_angular_speed_rad_s() const {
  return duration_s_ > 0 ? kPi / 2 * request_.delta_rot_F.norm() / duration_s_ : 0.0;
}

RsrSetPoint TimedMove::Evaluate(double time_s) const noexcept {
  RsrSetPoint out;
  out.time_s = time_s;
  const double t = time_s - request_.start_time_s;
  Vector6d delta;
  delta << request_.delta_p_F, request_.delta_rot_F;
  if (t <= 0 || duration_s_ == 0) {  // eq. 9, first case (and a zero move)
    out.X_FM = t <= 0 ? X_FM_start_ : X_FM_end_;
    out.displacement = t <= 0 ? Vector6d::Zero() : delta;
    return out;
  }
  if (t >= duration_s_) {  // eq. 9, second case: exactly the end pose
    out.X_FM = X_FM_end_;
    out.displacement = delta;
    return out;
  }
  // eq. 9, third case: dx/2 · sin(pi·tau - pi/2) + dx/2.
  const double w = kPi / duration_s_;
  const double s = 0.5 * std::sin(w * t - kPi / 2) + 0.5;
  const double s_dot = 0.5 * w * std::cos(w * t - kPi / 2);
  const double s_ddot = -0.5 * w * w * std::sin(w * t - kPi / 2);
  out.displacement = s * delta;
  out.velocity = s_dot * delta;
  out.acceleration = s_ddot * delta;
  out.X_FM.translation() = X_FM_start_.translation() + s * request_.delta_p_F;
  out.X_FM.linear() = RotationFromVector(s * request_.delta_rot_F) * X_FM_start_.linear();
  return out;
}

}  // namespace robossis::transfer
