#include "robot/actuation/actuator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace robossis::actuation {

const char* ToString(ActuationStatus status) {
  switch (status) {
    case ActuationStatus::kOk: return "ok";
    case ActuationStatus::kJointLimit: return "joint_limit";
    case ActuationStatus::kRateLimit: return "rate_limit";
    case ActuationStatus::kSingular: return "singular";
  }
  return "unknown";
}

namespace {
const ActuationConfig& Validated(const ActuationConfig& config) {
  config.Validate();
  return config;
}
}  // namespace

Actuator::Actuator(const robot::RsrModel& model, const ActuationConfig& config, const Eigen::Isometry3d& X_FM_start,
                   double start_time_s)
    : model_(model), config_(Validated(config)), time_s_(start_time_s) {
  const robot::RsrIkResult ik = robot::CalcInverseKinematics(model, X_FM_start);
  if (!ik.feasible) throw std::invalid_argument("actuation: the start pose is outside the RSR's joint limits");
  q0_ = ik.joints.actuated();
  q_ = q0_;
  const robot::RsrLimits& lim = model.limits();
  for (int i = 0; i < robot::kNumArms; ++i) {
    q_min_[robot::ThetaIndex(i)] = -lim.rotary_max_rad;
    q_max_[robot::ThetaIndex(i)] = lim.rotary_max_rad;
    q_min_[robot::StrokeIndex(i)] = lim.stroke_min_m;
    q_max_[robot::StrokeIndex(i)] = lim.stroke_max_m;
  }
  for (int m = 0; m < kNumMotors; ++m) pulses_[m] = PulseGenerator(config.motors[m].steps_per_unit);
  out_.command.time_s = start_time_s;
  out_.command.q = q_;
}

const ActuationOutput& Actuator::Tick(double time_s, const Eigen::Isometry3d& X_FM, const Vector6d& twist_F,
                                      double max_interval_s) noexcept {
  const double t_prev = std::max(time_s_, time_s - max_interval_s);
  const double dt = time_s - t_prev;  // eq. 16: t_clock(t) - t_clock(t-1), the real tick spacing (bounded)
  time_s_ = time_s;
  out_.status = ActuationStatus::kOk;
  out_.limit_flags = 0;
  out_.rate_flags = 0;
  out_.num_events = 0;

  // eq. 15: q_dot = J x_dot, with J at the new pose (Euler backward uses the velocity at the end of the step).
  const Matrix6d J = robot::CalcJacobian(model_, X_FM);
  robot::RsrJointVector q_dot = J * twist_F;
  if (!q_dot.allFinite() || !(dt >= 0)) {
    out_.status = ActuationStatus::kSingular;
    q_dot.setZero();
  } else if (config_.ik_correction_gain_per_s > 0) {
    // Closed-loop correction toward IK(x): bounds the first-order error of the integration.
    const robot::RsrIkResult ik = robot::CalcInverseKinematics(model_, X_FM);
    const robot::RsrJointVector q_ik = ik.joints.actuated();
    // At most the whole error in one tick (gain · dt <= 1), however long the tick: a larger gain would overshoot.
    const double gain = dt > 0 ? std::min(config_.ik_correction_gain_per_s, 1.0 / dt) : 0.0;
    if (q_ik.allFinite()) q_dot += gain * (q_ik - q_);
  }

  // eq. 16 with K = 1 in joint units: q(t) = q(t-1) + dt · q_dot(t). Shorten the step to stay legal.
  const robot::RsrJointVector dq = dt * q_dot;
  double lambda = 1.0;
  for (int i = 0; i < kNumMotors; ++i) {
    double li = 1.0;
    if (q_[i] + dq[i] > q_max_[i]) li = dq[i] > 0 ? std::max(0.0, (q_max_[i] - q_[i]) / dq[i]) : 1.0;
    if (q_[i] + dq[i] < q_min_[i]) li = dq[i] < 0 ? std::max(0.0, (q_min_[i] - q_[i]) / dq[i]) : 1.0;
    if (li < 1.0) out_.limit_flags |= static_cast<std::uint8_t>(1u << i);
    // The step rate: at most max_step_rate · dt steps this tick.
    const double steps = std::abs(dq[i]) * config_.motors[i].steps_per_unit;
    const double max_steps = config_.motors[i].max_step_rate_hz * dt;
    if (steps > max_steps) {
      li = std::min(li, max_steps / steps);
      out_.rate_flags |= static_cast<std::uint8_t>(1u << i);
    }
    lambda = std::min(lambda, li);
  }
  if (out_.limit_flags != 0) {
    out_.status = ActuationStatus::kJointLimit;
  } else if (out_.rate_flags != 0) {
    out_.status = ActuationStatus::kRateLimit;
  }
  out_.fraction = lambda;
  q_ += lambda * dq;
  for (int i = 0; i < kNumMotors; ++i) q_[i] = std::clamp(q_[i], q_min_[i], q_max_[i]);  // rounding guard
  out_.command.time_s = time_s;
  out_.command.q = q_;
  out_.command.q_dot = dt > 0 ? robot::RsrJointVector(lambda * q_dot) : robot::RsrJointVector::Zero();

  // eq. 17: the pulses of each motor over this tick.
  for (int m = 0; m < kNumMotors; ++m) {
    const int n = pulses_[m].Advance(t_prev, time_s, q_[m] - q0_[m], m, out_.events.data() + out_.num_events,
                                     kMaxStepsPerTickPerMotor);
    out_.num_events += n;
    out_.steps[m] = pulses_[m].steps();
    out_.step_error[m] = static_cast<double>(pulses_[m].steps()) - pulses_[m].commanded_steps();
  }
  return out_;
}

void Actuator::Resync(double time_s, const robot::RsrJointVector& q) noexcept {
  for (int m = 0; m < kNumMotors; ++m) {
    if (!std::isfinite(q[m])) continue;
    q_[m] = std::clamp(q[m], q_min_[m], q_max_[m]);
    // The commanded step count s = (q - q0) · steps_per_unit stays where it is: the zero moves instead.
    q0_[m] = q_[m] - pulses_[m].commanded_steps() / config_.motors[m].steps_per_unit;
  }
  time_s_ = time_s;
  out_.command.time_s = time_s;
  out_.command.q = q_;
  out_.command.q_dot.setZero();
  out_.num_events = 0;
  out_.fraction = 1;
}

}  // namespace robossis::actuation
