#include "haptics/transfer/motion_transfer.h"

namespace robossis::transfer {

namespace {
const TransferConfig& Validated(const TransferConfig& config) {
  config.Validate();
  return config;
}

// Moves `from` toward `to` by at most `step` (norm), returns the new point.
Eigen::Vector3d StepToward(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double step) noexcept {
  return from + ClampNorm(to - from, step);
}
}  // namespace

MotionTransfer::MotionTransfer(const TransferConfig& config, const Eigen::Isometry3d& X_FM_start)
    : config_(Validated(config)),
      dt_slow_(1.0 / config.rates.transfer_rate_hz),
      dt_fast_(1.0 / config.rates.actuation_rate_hz),
      mapper_(config.mapping, config.caps),
      upsampler_(config.rates.upsampling_ratio(), Vector6d::Zero()),
      moving_average_(config.filter.moving_average_window, Vector6d::Zero()),
      kalman_(1.0 / config.rates.actuation_rate_hz, config.filter.kalman_jerk_psd,
              config.filter.kalman_measurement_std_m, Vector6d::Zero()),
      guard_(1.0 / config.rates.actuation_rate_hz, config.caps, config.filter.guard_position_gain_per_s,
             config.filter.guard_time_constant_s, Vector6d::Zero()),
      X_FM_start_(X_FM_start) {
  set_point_.X_FM = X_FM_start;
}

void MotionTransfer::Rebase(const Eigen::Isometry3d& X_FM) noexcept {
  // The filters are fixed-size: rebuilding them allocates nothing, and the config was validated at construction.
  // The Kalman filter keeps its steady-state covariance (its construction iterates the Riccati recursion).
  upsampler_ = LinearUpsampler(config_.rates.upsampling_ratio(), Vector6d::Zero());
  moving_average_ = MovingAverage(config_.filter.moving_average_window, Vector6d::Zero());
  kalman_.Reset(Vector6d::Zero());
  guard_ = CapGuard(dt_fast_, config_.caps, config_.filter.guard_position_gain_per_s,
                    config_.filter.guard_time_constant_s, Vector6d::Zero());
  const bool engaged = mapper_.clutch_engaged();
  mapper_.SetClutch(false);
  mapper_.SetClutch(engaged);  // the next engaged sample anchors
  goal_.setZero();
  target_.setZero();
  fresh_since_tick_ = false;
  stale_s_ = 0;
  X_FM_start_ = X_FM;
  set_point_.X_FM = X_FM;
  set_point_.displacement.setZero();
  set_point_.velocity.setZero();
  set_point_.acceleration.setZero();
}

SampleVerdict MotionTransfer::PushHcSample(const HcSample& sample) noexcept {
  MappingIncrement increment;
  const SampleVerdict verdict = mapper_.Push(sample, increment);
  switch (verdict) {
    case SampleVerdict::kAccepted:
      ++counters_.accepted;
      goal_ += increment.delta_F;  // eq. 10
      fresh_since_tick_ = true;
      info_.scale_linear = increment.scale_linear;
      info_.scale_angular = increment.scale_angular;
      info_.hc_speed_m_s = increment.hc_speed_m_s;
      info_.hc_angular_speed_rad_s = increment.hc_angular_speed_rad_s;
      break;
    case SampleVerdict::kAnchored: ++counters_.anchored; break;
    case SampleVerdict::kRepeated: ++counters_.repeated; break;
    case SampleVerdict::kLate: ++counters_.late; break;
    case SampleVerdict::kInvalid: ++counters_.invalid; break;
    case SampleVerdict::kClutchOpen: ++counters_.clutch_open; break;
  }
  return verdict;
}

bool MotionTransfer::predicting() const {
  return config_.filter.kalman_enabled && mapper_.clutch_engaged() && stale_s_ > 0 &&
         stale_s_ <= config_.mapping.max_prediction_s;
}

void MotionTransfer::TransferTick() noexcept {
  stale_s_ = fresh_since_tick_ ? 0.0 : stale_s_ + dt_slow_;
  fresh_since_tick_ = false;
  const double max_v = config_.caps.max_linear_speed_m_s * config_.mapping.cap_headroom;
  const double max_w = config_.caps.max_angular_speed_rad_s * config_.mapping.cap_headroom;
  // Bound the backlog a stall left: keep at most max_backlog_s of motion at the cap, drop the rest.
  const double backlog_v = max_v * config_.mapping.max_backlog_s + max_v * dt_slow_;
  const double backlog_w = max_w * config_.mapping.max_backlog_s + max_w * dt_slow_;
  const Eigen::Vector3d lin = goal_.head<3>() - target_.head<3>();
  const Eigen::Vector3d ang = goal_.tail<3>() - target_.tail<3>();
  const Eigen::Vector3d lin_kept = ClampNorm(lin, backlog_v);
  const Eigen::Vector3d ang_kept = ClampNorm(ang, backlog_w);
  counters_.dropped_backlog_m += (lin - lin_kept).norm();
  counters_.dropped_backlog_rad += (ang - ang_kept).norm();
  goal_.head<3>() = target_.head<3>() + lin_kept;
  goal_.tail<3>() = target_.tail<3>() + ang_kept;
  // Release toward the goal at no more than the caps.
  target_.head<3>() = StepToward(target_.head<3>(), goal_.head<3>(), max_v * dt_slow_);
  target_.tail<3>() = StepToward(target_.tail<3>(), goal_.tail<3>(), max_w * dt_slow_);
  upsampler_.SetTarget(target_);
  info_.goal = goal_;
  info_.target = target_;
}

const RsrSetPoint& MotionTransfer::ActuationTick() noexcept {
  ++fast_ticks_;
  const Vector6d upsampled = upsampler_.Next();
  const Vector6d averaged = moving_average_.Step(upsampled);
  Vector6d p_ref = averaged;
  Vector6d v_ref = Vector6d::Zero();
  if (config_.filter.kalman_enabled) {
    if (predicting()) {
      kalman_.Predict();  // bridge the gap: no new measurement
    } else {
      kalman_.Step(averaged);  // eq. 12
    }
    p_ref = kalman_.state().row(0).transpose();
    v_ref = kalman_.state().row(1).transpose();
  }  // without the Kalman filter there is no velocity estimate: the guard follows by position feedback alone
  guard_.Step(p_ref, v_ref);

  set_point_.time_s = static_cast<double>(fast_ticks_) * dt_fast_;
  set_point_.displacement = guard_.position();
  set_point_.velocity = guard_.velocity();
  set_point_.acceleration = guard_.acceleration();
  set_point_.X_FM.translation() = X_FM_start_.translation() + guard_.position().head<3>();
  // Orientation: the fixed-frame rotation increment of this tick, R_new = Exp(dphi) R_old.
  const Eigen::Vector3d dphi = guard_.last_increment().tail<3>();
  if (dphi.squaredNorm() > 0) {
    Eigen::Matrix3d R = RotationFromVector(dphi) * set_point_.X_FM.linear();
    // Re-orthonormalise so that an hour of products cannot drift off SO(3).
    const Eigen::Quaterniond q(R);
    set_point_.X_FM.linear() = q.normalized().toRotationMatrix();
  }
  return set_point_;
}

}  // namespace robossis::transfer
