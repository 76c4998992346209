#pragma once
// The 10 kHz signal chain of the motion transfer (paper §V, Fig. 8): linear up-sampling of the 1 kHz incremental
// trajectory, a moving average, the Kalman filter of eq. 12 with a constant-acceleration model, and the cap guard
// that makes the speed caps a guarantee. Every class is sized at construction; every Step() is allocation-free.

#include <array>

#include <Eigen/Core>

#include "haptics/transfer/transfer_config.h"
#include "src/core/pose.h"

namespace robossis::transfer {

// 1 kHz → 10 kHz by linear interpolation between the last two 1 kHz targets (one slow tick of delay).
class LinearUpsampler {
 public:
  LinearUpsampler(int ratio, const Vector6d& initial);
  void SetTarget(const Vector6d& target) noexcept;  // once per slow tick
  Vector6d Next() noexcept;                           // once per fast tick; holds the target if no new one came
 private:
  int ratio_;
  int index_;
  Vector6d from_;
  Vector6d to_;
};

// Moving average over the last `window` fast samples (a convex combination: it never increases a speed).
class MovingAverage {
 public:
  MovingAverage(int window, const Vector6d& initial);
  Vector6d Step(const Vector6d& x) noexcept;

 private:
  std::array<Vector6d, kMaxMovingAverageWindow> buffer_;
  int window_;
  int next_ = 0;
};

// eq. 12: x(t+1) = F x(t) + K(t+1) (z(t+1) - H F x(t)), per axis a constant-acceleration state [pos, vel, acc] with
// white-jerk process noise (spectral density q) and a position measurement (std r). The six axes share F, H, Q, R,
// hence one covariance P and one gain K; the state is a 3 x 6 matrix (rows pos/vel/acc, columns the six axes).
class KalmanCa {
 public:
  using State = Eigen::Matrix<double, 3, 6>;
  KalmanCa(double dt_s, double jerk_psd, double measurement_std, const Vector6d& initial_position);

  void Step(const Vector6d& measured_position) noexcept;
  // At rest at `position` with the steady-state covariance, as after construction (no Riccati iteration).
  void Reset(const Vector6d& position) noexcept;
  // Prediction only (no measurement: the HC stream is stale); the covariance grows by Q.
  void Predict() noexcept;
  const State& state() const { return x_; }
  const Eigen::Matrix3d& covariance() const { return P_; }
  const Eigen::Vector3d& gain() const { return K_; }

 private:
  Eigen::Matrix3d F_;
  Eigen::Matrix3d Q_;
  double r2_;
  Eigen::Matrix3d P_;
  Eigen::Matrix3d P_steady_;  // the Riccati fixed point, computed once at construction
  Eigen::Vector3d K_;
  State x_;
};

// The cap guard: v_des = clamp(v_ref + k_p (p_ref - y)) on the ball of each cap (linear, angular), then two
// first-order low-passes with time constant tau give the set-point velocity, and y += v dt. Each low-pass step is a
// convex combination of points inside the ball, so |v| never exceeds the caps (exactly, on the norm), and the
// acceleration stays continuous. Position feedback removes any offset, so the set-point converges to p_ref.
class CapGuard {
 public:
  CapGuard(double dt_s, const SpeedCaps& caps, double position_gain_per_s, double time_constant_s,
           const Vector6d& initial_position);

  void Step(const Vector6d& reference_position, const Vector6d& reference_velocity) noexcept;
  const Vector6d& position() const { return y_; }
  const Vector6d& velocity() const { return v_; }
  const Vector6d& acceleration() const { return a_; }
  // Velocity change of the last step (rad or m per step) — exposed for the set-point pose integration.
  const Vector6d& last_increment() const { return dy_; }

 private:
  double dt_;
  double max_v_;
  double max_w_;
  double kp_;
  double alpha_;
  Vector6d y_;
  Vector6d u1_ = Vector6d::Zero();
  Vector6d v_ = Vector6d::Zero();
  Vector6d a_ = Vector6d::Zero();
  Vector6d dy_ = Vector6d::Zero();
};

// Shrinks the 3-vector to norm <= cap (no-op inside the ball).
inline Eigen::Vector3d ClampNorm(const Eigen::Vector3d& v, double cap) noexcept {
  const double n = v.norm();
  return n > cap ? Eigen::Vector3d(v * (cap / n)) : v;
}

}  // namespace robossis::transfer
