#include "src/teleop/move_validation.h"

#include <algorithm>
#include <cmath>

namespace robossis::teleop {

PathVerdict ValidateMove(const transfer::TimedMove& move, const robot::RsrModel& model, const SetPointLimits& limits,
                         double actuation_rate_hz) {
  const double dt = 1.0 / actuation_rate_hz;
  const double t0 = move.end_time_s() - move.duration_s();
  // At least one tick: the last sample is always the end pose, however short the move.
  const auto n = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(move.duration_s() / dt - 1e-9)));
  PathVerdict out;
  // The whole path by the exact IK first, so that a path through the wall is named as such whatever its speed.
  for (std::size_t k = 0; k <= n; ++k) {
    const double t = std::min(t0 + k * dt, move.end_time_s());
    const robot::RsrIkResult ik = robot::CalcInverseKinematics(model, move.Evaluate(t).X_FM);
    const robot::RsrLimitCheck tightest = ik.tightest();
    if (k == 0 || tightest.margin < out.tightest.margin) out.tightest = tightest;
    if (!ik.feasible) {
      out.verdict = SetPointVerdict::kInfeasible;
      out.index = k;
      out.time_s = t;
      out.tightest = tightest;
      return out;
    }
  }
  const bool moves = move.peak_linear_speed_m_s() > 0 || move.peak_angular_speed_rad_s() > 0;
  // A move shorter than one tick has no tick inside it: the follower would take the whole change in one tick, at
  // whatever speed that means, and the samples would see only its ends at rest. (1e-9: the rounding of a duration
  // that is exactly one tick.)
  if (moves && move.duration_s() < dt * (1 - 1e-9)) {
    out.verdict = SetPointVerdict::kTooFast;
    out.shorter_than_a_tick = true;
    out.time_s = t0;
    return out;
  }
  // The peak of the timed profile (eq. 9: pi/2 · |dx| / duration, at mid-move) against the caps, with the
  // validator's tolerance: samples at the ticks can straddle the peak, and a pose difference over a tick is a mean.
  const double slack = 1.0 + limits.cap_tolerance;
  if (move.peak_linear_speed_m_s() > slack * limits.caps.max_linear_speed_m_s ||
      move.peak_angular_speed_rad_s() > slack * limits.caps.max_angular_speed_rad_s) {
    out.verdict = SetPointVerdict::kTooFast;
    out.index = n / 2;
    out.time_s = t0 + 0.5 * move.duration_s();
    return out;
  }
  SetPointValidator validator(model, limits);
  for (std::size_t k = 0; k <= n; ++k) {
    const double t = std::min(t0 + k * dt, move.end_time_s());
    const transfer::RsrSetPoint sp = move.Evaluate(t);
    SetPointSample sample;
    sample.time_s = t0 + k * dt;
    sample.X_FM = sp.X_FM;
    sample.twist_F = sp.velocity;
    const SetPointVerdict v = validator.Check(sample);
    if (v != SetPointVerdict::kAccepted) {
      out.verdict = v;
      out.index = k;
      out.time_s = t;
      out.tightest = validator.tightest();
      return out;
    }
  }
  return out;
}

}  // namespace robossis::teleop
