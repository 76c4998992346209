#include "haptics/transfer/signal_filters.h"

#include <algorithm>
#include <cmath>

namespace robossis::transfer {

LinearUpsampler::LinearUpsampler(int ratio, const Vector6d& initial)
    : ratio_(std::max(1, ratio)), index_(std::max(1, ratio)), from_(initial), to_(initial) {}

void LinearUpsampler::SetTarget(const Vector6d& target) noexcept {
  // The new segment starts where the output is now, so a late slow tick never makes the output jump back.
  from_ = index_ >= ratio_ ? to_ : Vector6d(from_ + (to_ - from_) * (static_cast<double>(index_) / ratio_));
  to_ = target;
  index_ = 0;
}

Vector6d LinearUpsampler::Next() noexcept {
  if (index_ < ratio_) ++index_;
  const double s = static_cast<double>(index_) / ratio_;
  return from_ + (to_ - from_) * s;
}

MovingAverage::MovingAverage(int window, const Vector6d& initial)
    : window_(std::clamp(window, 1, kMaxMovingAverageWindow)) {
  buffer_.fill(initial);
}

Vector6d MovingAverage::Step(const Vector6d& x) noexcept {
  buffer_[next_] = x;
  next_ = (next_ + 1) % window_;
  // Summed afresh every step: no running sum, so no rounding drift over hours.
  Vector6d sum = Vector6d::Zero();
  for (int i = 0; i < window_; ++i) sum += buffer_[i];
  return sum / window_;
}

KalmanCa::KalmanCa(double dt, double q, double measurement_std, const Vector6d& initial_position) {
  // Constant-acceleration transition F and the discretised white-jerk process noise Q.
  F_ << 1, dt, 0.5 * dt * dt, 0, 1, dt, 0, 0, 1;
  const double dt2 = dt * dt, dt3 = dt2 * dt, dt4 = dt3 * dt, dt5 = dt4 * dt;
  Q_ << dt5 / 20, dt4 / 8, dt3 / 6, dt4 / 8, dt3 / 3, dt2 / 2, dt3 / 6, dt2 / 2, dt;
  Q_ *= q;
  r2_ = measurement_std * measurement_std;
  // Start at rest at the initial position with the steady-state covariance (the Riccati recursion iterated to its
  // fixed point), so the filter has no start-up transient: its gain is the same from the first tick.
  P_ = Eigen::Matrix3d::Zero();
  P_.diagonal() << r2_, r2_, r2_;
  for (int i = 0; i < 200000; ++i) {
    const Eigen::Matrix3d P_pred = F_ * P_ * F_.transpose() + Q_;
    const Eigen::Vector3d K = P_pred.col(0) / (P_pred(0, 0) + r2_);
    Eigen::Matrix3d IKH = Eigen::Matrix3d::Identity();
    IKH.col(0) -= K;
    const Eigen::Matrix3d P_next = IKH * P_pred * IKH.transpose() + r2_ * K * K.transpose();
    const double change = (P_next - P_).norm() / P_next.norm();
    P_ = 0.5 * (P_next + P_next.transpose());
    if (change < 1e-13) break;
  }
  P_steady_ = P_;
  Reset(initial_position);
}

void KalmanCa::Reset(const Vector6d& position) noexcept {
  P_ = P_steady_;
  K_.setZero();
  x_.setZero();
  x_.row(0) = position.transpose();
}

void KalmanCa::Step(const Vector6d& z) noexcept {
  // Predict.
  const State x_pred = F_ * x_;
  Eigen::Matrix3d P_pred = F_ * P_ * F_.transpose() + Q_;
  // Update with H = [1 0 0]: S = P00 + r^2, K = P(:,0) / S.
  const double S = P_pred(0, 0) + r2_;
  K_ = P_pred.col(0) / S;
  // eq. 12: x(t+1) = F x(t) + K (z - H F x(t)).
  x_ = x_pred + K_ * (z.transpose() - x_pred.row(0));
  // Joseph form keeps P symmetric positive definite: (I - K H) P (I - K H)^T + K r^2 K^T.
  Eigen::Matrix3d IKH = Eigen::Matrix3d::Identity();
  IKH.col(0) -= K_;
  P_ = IKH * P_pred * IKH.transpose() + r2_ * K_ * K_.transpose();
  P_ = 0.5 * (P_ + P_.transpose()).eval();
}

void KalmanCa::Predict() noexcept {
  x_ = (F_ * x_).eval();
  P_ = F_ * P_ * F_.transpose() + Q_;
  P_ = 0.5 * (P_ + P_.transpose()).eval();
}

CapGuard::CapGuard(double dt, const SpeedCaps& caps, double kp, double tau, const Vector6d& initial_position)
    : dt_(dt),
      // A hair below the caps, so rounding in the low-pass steps can never carry a speed past them.
      max_v_(caps.max_linear_speed_m_s * (1 - 1e-9)),
      max_w_(caps.max_angular_speed_rad_s * (1 - 1e-9)),
      kp_(kp),
      alpha_(tau > 0 ? 1.0 - std::exp(-dt / tau) : 1.0),
      y_(initial_position) {}

void CapGuard::Step(const Vector6d& p_ref, const Vector6d& v_ref) noexcept {
  const Vector6d v_des_raw = v_ref + kp_ * (p_ref - y_);
  Vector6d v_des;
  v_des << ClampNorm(v_des_raw.head<3>(), max_v_), ClampNorm(v_des_raw.tail<3>(), max_w_);
  // Two convex low-pass steps: u1 and v stay inside the balls if v_des is inside.
  u1_ += alpha_ * (v_des - u1_);
  const Vector6d v_new = v_ + alpha_ * (u1_ - v_);
  a_ = (v_new - v_) / dt_;
  v_ = v_new;
  dy_ = v_ * dt_;  // Euler step: the set-point moves by exactly v dt, so its finite-difference speed is |v|
  y_ += dy_;
}

}  // namespace robossis::transfer
