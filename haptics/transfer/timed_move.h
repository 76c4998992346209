#pragma once
// Time-controlled moves (paper eq. 9) for the GUI and scripted motions: from a start pose, a change of any of the six
// DOF (or all together) over a given duration, or at a given peak speed.
//
// eq. 9 per DOF: x(t) = x0 for t < t0; x0 + dx for t > t0 + dt; otherwise
//   dx/2 · sin(180°/dt · (t - t0) - 90°) + x0 + dx/2  =  x0 + dx · (1 - cos(pi·tau)) / 2,  tau = (t - t0) / dt.
// All six DOF share the same profile s(tau), so the path is a straight line in position and a rotation about one
// fixed axis; the velocity is continuous (zero at both ends) and the endpoints are exact.

#include <Eigen/Geometry>

#include "haptics/transfer/set_point.h"
#include "haptics/transfer/transfer_config.h"

namespace robossis::transfer {

struct TimedMoveRequest {
  Eigen::Vector3d delta_p_F = Eigen::Vector3d::Zero();    // m, in the fixed frame
  Eigen::Vector3d delta_rot_F = Eigen::Vector3d::Zero();  // rotation vector (rad) about fixed-frame axes
  double start_time_s = 0;
};

class TimedMove {
 public:
  // A move of the given duration (s > 0, or 0 for a zero change). Throws std::invalid_argument on bad values.
  TimedMove(const Eigen::Isometry3d& X_FM_start, const TimedMoveRequest& request, double duration_s);

  // The duration at which the peak speeds (pi/2 · |dx| / dt for eq. 9) equal the given speeds.
  static double DurationForPeakSpeeds(const TimedMoveRequest& request, double linear_speed_m_s,
                                      double angular_speed_rad_s);

  // The set-point at time t (any t; constant before and after the move). Allocation-free.
  RsrSetPoint Evaluate(double time_s) const noexcept;

  double duration_s() const { return duration_s_; }
  double end_time_s() const { return request_.start_time_s + duration_s_; }
  const Eigen::Isometry3d& X_FM_end() const { return X_FM_end_; }
  // Peak speeds of eq. 9: pi/2 · |dx| / dt.
  double peak_linear_speed_m_s() const;
  double peak_angular_speed_rad_s() const;

 private:
  Eigen::Isometry3d X_FM_start_;
  Eigen::Isometry3d X_FM_end_;
  TimedMoveRequest request_;
  double duration_s_;
};

}  // namespace robossis::transfer
