#pragma once
// The spring-damper wall law of eq. 18–19 and the linearly weighted moving average of §VI-A, shared by the methods.

#include <array>

#include <Eigen/Core>

#include "src/core/pose.h"

namespace robossis::haptics {

// eq. 18–19 constants, SI. Defaults: the paper's k_f = 2000 N/m, c_f = 15 N·s/m, k_τ = 0.12 N·m/deg,
// c_τ = 0.001 N·m·s/deg (converted to per-radian).
struct WallLawParams {
  double k_f_n_per_m = 2000.0;
  double c_f_ns_per_m = 15.0;
  double k_tau_nm_per_rad = 0.12 * 180.0 / 3.14159265358979323846;
  double c_tau_nms_per_rad = 0.001 * 180.0 / 3.14159265358979323846;
};

// eq. 18 with our sign reading: d_in_F is the penetration vector pointing back INTO the allowed region (README,
// "Reading of eq. 18–21"), so the spring term pushes the hand back inside and the damper opposes the HC velocity.
//   F = k_f · d_in − c_f · v_HC          (eq. 18)
//   τ = k_τ · θ_in − c_τ · ω_HC          (eq. 19)
inline Eigen::Vector3d WallForce(const WallLawParams& p, const Eigen::Vector3d& d_in_F,
                                 const Eigen::Vector3d& v_F) noexcept {
  return p.k_f_n_per_m * d_in_F - p.c_f_ns_per_m * v_F;  // eq. 18
}
inline Eigen::Vector3d WallTorque(const WallLawParams& p, const Eigen::Vector3d& theta_in_F,
                                  const Eigen::Vector3d& w_F) noexcept {
  return p.k_tau_nm_per_rad * theta_in_F - p.c_tau_nms_per_rad * w_F;  // eq. 19
}

// Linearly weighted moving average over the last `window` wrenches (paper §VI-A: window 5, "the latest forces and
// torques having higher priority"): weight k for the k-th oldest of the window, so with 5 samples the weights are
// 1/15, 2/15, 3/15, 4/15, 5/15, newest heaviest. Until the window has filled, the weights of the samples present are
// renormalised (1 sample: weight 1; 2 samples: 1/3, 2/3; ...). Fixed capacity: no allocation.
class WeightedMovingAverage {
 public:
  static constexpr int kMaxWindow = 16;
  explicit WeightedMovingAverage(int window = 5);  // throws std::invalid_argument outside [1, kMaxWindow]

  void Reset() noexcept { count_ = 0; next_ = 0; }
  // Pushes a sample and returns the weighted mean of the window.
  Vector6d Filter(const Vector6d& sample) noexcept;
  int window() const { return window_; }
  // Weight of the sample `age` ticks old (0 = newest) once the window is full: (window − age) / (window(window+1)/2).
  double Weight(int age) const noexcept;

 private:
  int window_;
  int count_ = 0;
  int next_ = 0;
  std::array<Vector6d, kMaxWindow> samples_{};
};

}  // namespace robossis::haptics
