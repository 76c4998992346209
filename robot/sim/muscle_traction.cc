#include "robot/sim/muscle_traction.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace robossis::sim {

MuscleTraction::MuscleTraction(const TractionConfig& config, const Eigen::Vector3d& axis_F,
                               const Eigen::Vector3d& site_F, const Eigen::Isometry3d& X_FM_aligned)
    : config_(config), axis_F_(axis_F.normalized()) {
  // Two unit vectors across the axis.
  const Eigen::Vector3d ref = std::abs(axis_F_.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = (ref - ref.dot(axis_F_) * axis_F_).normalized();
  const Eigen::Vector3d e2 = axis_F_.cross(e1);
  const Eigen::Isometry3d X_MF = X_FM_aligned.inverse();
  const int n = config.muscle_count;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * std::numbers::pi * k / n;
    const Eigen::Vector3d radial = config.muscle_radius_m * (std::cos(a) * e1 + std::sin(a) * e2);
    anchors_proximal_F_.push_back(site_F + radial - config.anchor_distance_m * axis_F_);
    anchors_distal_M_.push_back(X_MF * (site_F + radial + config.anchor_distance_m * axis_F_));
  }
  rest_length_m_.assign(n, 0.0);
  line_stiffness_ = config.axial_stiffness_n_per_m / n;
  line_damping_ = config.damping_n_s_per_m / n;
  R_ref_ = X_FM_aligned.linear();
}

void MuscleTraction::Calibrate(const Eigen::Isometry3d& X_FM_ref, const Eigen::Matrix3d& R_FM_twist_ref, double load_n,
                               double load_nm, double twist_sign) {
  if (!(load_n >= 0) || !(load_nm >= 0)) throw std::invalid_argument("traction: loads must be >= 0");
  R_ref_ = R_FM_twist_ref;
  enabled_lines_ = load_n > 0;
  enabled_twist_ = load_nm > 0;
  // Equal tension T in every line so that the axial sum is load_n: T * sum(n_k · axis) = load_n.
  double axial_sum = 0;
  std::vector<double> length(rest_length_m_.size());
  for (std::size_t k = 0; k < length.size(); ++k) {
    const Eigen::Vector3d line = X_FM_ref * anchors_distal_M_[k] - anchors_proximal_F_[k];
    length[k] = line.norm();
    axial_sum += line.dot(axis_F_) / length[k];
  }
  if (enabled_lines_ && !(axial_sum > 0.5)) {
    throw std::invalid_argument("traction: at the reference pose the muscle lines do not run along the femur");
  }
  const double tension = enabled_lines_ ? load_n / axial_sum : 0.0;
  for (std::size_t k = 0; k < length.size(); ++k) {
    rest_length_m_[k] = length[k] - tension / line_stiffness_;
    if (!(rest_length_m_[k] > 0)) throw std::invalid_argument("traction: load too large for the muscle stiffness");
  }
  // The torsional element's rest twist, measured from the reference pose: k_t * rest = load_nm.
  rest_twist_rad_ = enabled_twist_ ? std::copysign(load_nm / config_.torsional_stiffness_nm_per_rad, twist_sign) : 0.0;
}

TractionSample MuscleTraction::Evaluate(const Eigen::Isometry3d& X_FM, const Eigen::Vector3d& v_P_F,
                                        const Eigen::Vector3d& w_F) const noexcept {
  TractionSample out;
  const Eigen::Vector3d p = X_FM.translation();
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  if (enabled_lines_) {
    for (std::size_t k = 0; k < anchors_proximal_F_.size(); ++k) {
      const Eigen::Vector3d x = X_FM * anchors_distal_M_[k];
      const Eigen::Vector3d line = x - anchors_proximal_F_[k];
      const double length = line.norm();
      const Eigen::Vector3d n = line / length;
      const Eigen::Vector3d v_x = v_P_F + w_F.cross(x - p);
      const double tension = std::max(0.0, line_stiffness_ * (length - rest_length_m_[k]) + line_damping_ * n.dot(v_x));
      const Eigen::Vector3d f = -tension * n;  // pulls the distal anchor toward the proximal one
      force += f;
      moment += (x - p).cross(f);
    }
  }
  // Twist about the femur axis from the reference orientation (swing-twist decomposition).
  const Eigen::Quaterniond q_rel(X_FM.linear() * R_ref_.transpose());
  const double along = q_rel.vec().dot(axis_F_);
  out.twist_rad = 2.0 * std::atan2(along, q_rel.w());
  if (out.twist_rad > std::numbers::pi) out.twist_rad -= 2.0 * std::numbers::pi;
  if (out.twist_rad < -std::numbers::pi) out.twist_rad += 2.0 * std::numbers::pi;
  if (enabled_twist_) {
    out.twist_torque_nm = -config_.torsional_stiffness_nm_per_rad * (out.twist_rad - rest_twist_rad_) -
                          config_.torsional_damping_nm_s_per_rad * w_F.dot(axis_F_);
    moment += out.twist_torque_nm * axis_F_;
  }
  out.wrench_P_F << force, moment;
  out.axial_force_n = -force.dot(axis_F_);
  return out;
}

}  // namespace robossis::sim
