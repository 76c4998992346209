#include "src/teleop/setpoint_validator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace robossis::teleop {

const char* ToString(SetPointVerdict verdict) {
  switch (verdict) {
    case SetPointVerdict::kAccepted: return "accepted";
    case SetPointVerdict::kNotFinite: return "not_finite";
    case SetPointVerdict::kStale: return "stale";
    case SetPointVerdict::kOutOfOrder: return "out_of_order";
    case SetPointVerdict::kInfeasible: return "infeasible";
    case SetPointVerdict::kTooFast: return "too_fast";
    case SetPointVerdict::kTooAccelerating: return "too_accelerating";
  }
  return "unknown";
}

void SetPointLimits::Validate() const {
  const auto require = [](bool ok, const char* field, double value, const char* expected) {
    if (!ok) {
      throw std::invalid_argument(std::string("set-point limits: ") + field + " is " + std::to_string(value) +
                                  "; expected " + expected);
    }
  };
  require(std::isfinite(caps.max_linear_speed_m_s) && caps.max_linear_speed_m_s >= 0, "max_linear_speed_m_s",
          caps.max_linear_speed_m_s, "a finite speed >= 0");
  require(std::isfinite(caps.max_angular_speed_rad_s) && caps.max_angular_speed_rad_s >= 0,
          "max_angular_speed_rad_s", caps.max_angular_speed_rad_s, "a finite speed >= 0");
  require(std::isfinite(max_linear_accel_m_s2) && max_linear_accel_m_s2 > 0, "max_linear_accel_m_s2",
          max_linear_accel_m_s2, "a finite acceleration > 0");
  require(std::isfinite(max_angular_accel_rad_s2) && max_angular_accel_rad_s2 > 0, "max_angular_accel_rad_s2",
          max_angular_accel_rad_s2, "a finite acceleration > 0");
  require(std::isfinite(max_age_s) && max_age_s > 0 && max_age_s <= 1.0, "max_age_s", max_age_s, "0 < age <= 1 s");
  require(std::isfinite(cap_tolerance) && cap_tolerance >= 0 && cap_tolerance <= 0.5, "cap_tolerance",
          cap_tolerance, "0..0.5");
  require(std::isfinite(setpoint_period_s) && setpoint_period_s > 0 && setpoint_period_s <= 0.1, "setpoint_period_s",
          setpoint_period_s, "0 < T <= 0.1 s");
  require(std::isfinite(stamp_jitter_s) && stamp_jitter_s >= 0 && stamp_jitter_s <= 0.01, "stamp_jitter_s",
          stamp_jitter_s, "0..10 ms");
  require(std::isfinite(arrival_allowance_s) && arrival_allowance_s >= 0 && arrival_allowance_s <= 0.1,
          "arrival_allowance_s", arrival_allowance_s, "0..100 ms");
}

Vector6d CapStepToSpeeds(const Vector6d& step, const transfer::SpeedCaps& caps, double dt) noexcept {
  Vector6d out = step;
  const double lin = step.head<3>().norm(), ang = step.tail<3>().norm();
  const double lin_max = caps.max_linear_speed_m_s * dt, ang_max = caps.max_angular_speed_rad_s * dt;
  if (lin > lin_max) out.head<3>() *= lin_max / lin;
  if (ang > ang_max) out.tail<3>() *= ang_max / ang;
  return out;
}

SetPointSample SampleFromMessage(const SetPointMessage& m) noexcept {
  SetPointSample s;
  s.time_s = 1e-9 * static_cast<double>(m.stamp_ns);
  const Eigen::Quaterniond q(m.q_FM[0], m.q_FM[1], m.q_FM[2], m.q_FM[3]);
  s.X_FM = Eigen::Isometry3d::Identity();
  s.X_FM.linear() = q.toRotationMatrix();
  s.X_FM.translation() = Eigen::Vector3d(m.p_FM[0], m.p_FM[1], m.p_FM[2]);
  for (int i = 0; i < 6; ++i) s.twist_F[i] = m.twist_F[i];
  return s;
}

SetPointValidator::SetPointValidator(const robot::RsrModel& model, const SetPointLimits& limits)
    : model_(model), limits_(limits) {
  limits_.Validate();
}

std::uint64_t SetPointValidator::rejected() const noexcept {
  std::uint64_t n = 0;
  for (int i = 1; i < kNumSetPointVerdicts; ++i) n += counts_[i];
  return n;
}

SetPointVerdict SetPointValidator::Check(const SetPointSample& s, double interval_s) noexcept {
  if (!std::isfinite(s.time_s) || !s.X_FM.matrix().allFinite() || !s.twist_F.allFinite()) {
    return Count(SetPointVerdict::kNotFinite);
  }
  if (has_reference_ && !(s.time_s > reference_.time_s)) return Count(SetPointVerdict::kOutOfOrder);
  const robot::RsrIkResult ik = robot::CalcInverseKinematics(model_, s.X_FM);  // exact IK, eq. 5–8
  tightest_ = ik.tightest();
  if (!ik.feasible) return Count(SetPointVerdict::kInfeasible);

  const double slack = 1.0 + limits_.cap_tolerance;
  const double v_max = slack * limits_.caps.max_linear_speed_m_s;
  const double w_max = slack * limits_.caps.max_angular_speed_rad_s;
  // The stated twist (eq. 14's velocity) within the caps of eq. 11.
  if (s.twist_F.head<3>().norm() > v_max || s.twist_F.tail<3>().norm() > w_max) {
    return Count(SetPointVerdict::kTooFast);
  }
  if (has_reference_) {
    const double dt = interval_s > 0 ? interval_s : s.time_s - reference_.time_s;
    // The pose change since the previous set-point, whatever the twist claims.
    const double dp = (s.X_FM.translation() - reference_.X_FM.translation()).norm();
    const double dr = RotationAngleBetween(reference_.X_FM.linear(), s.X_FM.linear());
    if (dp > v_max * dt || dr > w_max * dt) return Count(SetPointVerdict::kTooFast);
    const double a = (s.twist_F.head<3>() - reference_.twist_F.head<3>()).norm() / dt;
    const double alpha = (s.twist_F.tail<3>() - reference_.twist_F.tail<3>()).norm() / dt;
    if (a > slack * limits_.max_linear_accel_m_s2 || alpha > slack * limits_.max_angular_accel_rad_s2) {
      return Count(SetPointVerdict::kTooAccelerating);
    }
  }
  reference_ = s;
  has_reference_ = true;
  return Count(SetPointVerdict::kAccepted);
}

SetPointVerdict SetPointValidator::CheckMessage(const SetPointMessage& m, double arrival_s, double now_s,
                                                SetPointSample& sample) noexcept {
  bool finite = std::isfinite(arrival_s) && std::isfinite(now_s);
  for (double v : m.p_FM) finite = finite && std::isfinite(v);
  for (double v : m.twist_F) finite = finite && std::isfinite(v);
  double q_norm_sq = 0;
  for (double v : m.q_FM) {
    finite = finite && std::isfinite(v);
    q_norm_sq += v * v;
  }
  if (!finite || std::abs(q_norm_sq - 1.0) > 1e-6) return Count(SetPointVerdict::kNotFinite);
  if (now_s - arrival_s > limits_.max_age_s) return Count(SetPointVerdict::kStale);
  if (has_sequence_ && m.leader_session == session_ && m.sequence <= sequence_) {
    return Count(SetPointVerdict::kOutOfOrder);
  }
  if (has_sequence_ && m.leader_session != session_) Reset();  // a restarted leader re-anchors
  sample = SampleFromMessage(m);
  // The follower's own clock: its time credit grows with the time between the arrivals it judges (starting at the
  // allowance when the reference is new) and each accepted set-point spends its interval. One period is always
  // allowed, or a leader at the caps would be refused whenever its set-points arrive on time.
  const double allowance = std::max(limits_.arrival_allowance_s, limits_.setpoint_period_s);
  credit_s_ = has_arrival_ ? credit_s_ + std::max(0.0, arrival_s - last_arrival_s_) : allowance;
  has_arrival_ = true;
  last_arrival_s_ = arrival_s;
  double interval_s = 0;
  if (has_reference_ && has_sequence_ && m.leader_session == session_) {
    const double by_sequence = static_cast<double>(m.sequence - sequence_) * limits_.setpoint_period_s;
    const double by_stamps = sample.time_s - reference_.time_s + limits_.stamp_jitter_s;
    // One step: no longer than the arrivals' interval plus the allowance. All steps: no more than the credit, so
    // that a forged interval never buys a faster sustained speed than the caps on the follower's clock.
    const double by_arrivals = arrival_s - reference_arrival_s_ + allowance;
    // Never 0 (Check() would take the stamps' difference): a spent credit judges over a sliver, refusing motion.
    interval_s = std::max(std::min({by_sequence, by_stamps, by_arrivals, credit_s_}), 1e-9);
  }
  const SetPointVerdict v = Check(sample, interval_s);
  if (v == SetPointVerdict::kAccepted) {
    credit_s_ -= interval_s;
    reference_arrival_s_ = arrival_s;
    has_sequence_ = true;
    session_ = m.leader_session;
    sequence_ = m.sequence;
  }
  return v;
}

}  // namespace robossis::teleop
