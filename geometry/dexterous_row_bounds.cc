#include "geometry/dexterous_row_bounds.h"

#include <algorithm>
#include <cmath>

namespace robossis::geometry {

DexterousRowBounds::DexterousRowBounds(const robot::RsrModel& rsr, const Eigen::Matrix3d& R_FM)
    : z_M_(R_FM.col(2)) {
  for (int i = 0; i < robot::kNumArms; ++i) c_F_[i] = rsr.p_FA(i) - R_FM * rsr.p_MB(i);
  const double ball = rsr.limits().stroke_max_m + kRowBoundSlackM;
  ball_sq_ = ball * ball;
  const double cone = rsr.limits().spherical_cone_max_rad + kRowBoundSlackRad;
  cos_sq_ = cone < M_PI / 2 ? std::cos(cone) * std::cos(cone) : 0.0;
}

bool DexterousRowBounds::Candidates(double y, double z, double x0, double spacing, int n, int* first,
                                    int* last) const noexcept {
  *first = 0;
  *last = n - 1;
  double x_lo = -HUGE_VAL, x_hi = HUGE_VAL;
  for (int i = 0; i < robot::kNumArms; ++i) {
    // The leg at x: w = u + s·e_x with s = x − c_x and u = (0, y − c_y, z − c_z).
    const Eigen::Vector3d u(0.0, y - c_F_[i].y(), z - c_F_[i].z());
    const double u_sq = u.squaredNorm();
    // Ball: s² + |u|² <= ball².
    const double room = ball_sq_ - u_sq;
    if (room < 0) return false;
    const double half = std::sqrt(room);
    x_lo = std::max(x_lo, c_F_[i].x() - half);
    x_hi = std::min(x_hi, c_F_[i].x() + half);
    // Cone (both nappes: a superset): (w·z_M)² >= cos²·|w|², a quadratic A s² + B s + C >= 0. With A < 0 (the ring
    // tilted less than 90° − cone from the row's axis, always so in the workspace) it holds between the roots;
    // otherwise the row is not bounded by this cone.
    const double a0 = u.dot(z_M_);
    const double A = z_M_.x() * z_M_.x() - cos_sq_;
    if (!(A < 0)) continue;
    const double B = 2 * a0 * z_M_.x();
    const double C = a0 * a0 - cos_sq_ * u_sq;
    const double disc = B * B - 4 * A * C;
    if (disc < 0) return false;
    const double root = std::sqrt(disc);
    x_lo = std::max(x_lo, c_F_[i].x() + (-B + root) / (2 * A));
    x_hi = std::min(x_hi, c_F_[i].x() + (-B - root) / (2 * A));
  }
  if (!(std::isfinite(x_lo) && std::isfinite(x_hi))) return true;  // not bounded (or not a number): test every node
  if (x_lo > x_hi) return false;
  // One node more at each end: the bound is exact to far less than a spacing, the nodes' own rounding aside.
  const double i_lo = std::ceil((x_lo - x0) / spacing) - 1;
  const double i_hi = std::floor((x_hi - x0) / spacing) + 1;
  if (i_hi < 0 || i_lo > n - 1) return false;
  *first = static_cast<int>(std::max(0.0, i_lo));
  *last = static_cast<int>(std::min(static_cast<double>(n - 1), i_hi));
  return *first <= *last;
}

}  // namespace robossis::geometry
