#include "calibration/reference_curve.h"

#include <algorithm>
#include <stdexcept>

#include "src/core/pose.h"

namespace robossis::calibration {

ReferenceCurve::ReferenceCurve(const PoseTrajectory& trajectory) : trajectory_(trajectory) {
  const std::size_t n = trajectory.size();
  if (n < 2) throw std::invalid_argument("reference curve: need at least 2 samples, got " + std::to_string(n));
  v_.resize(n);
  w_.resize(n);
  // Node rates from the neighbouring samples (central where both exist): the secant slopes averaged by time.
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = i == 0 ? 0 : i - 1, b = i + 1 < n ? i + 1 : n - 1;
    const double dt = trajectory.t_s[b] - trajectory.t_s[a];
    v_[i] = (trajectory.p[b] - trajectory.p[a]) / dt;
    w_[i] = RotationVector(trajectory.q[b].toRotationMatrix() * trajectory.q[a].toRotationMatrix().transpose()) / dt;
  }
}

bool ReferenceCurve::Evaluate(double t, ReferenceState& state) const {
  const std::vector<double>& ts = trajectory_.t_s;
  if (!(t >= ts.front()) || !(t <= ts.back())) return false;
  std::size_t hi = static_cast<std::size_t>(std::upper_bound(ts.begin(), ts.end(), t) - ts.begin());
  hi = std::clamp<std::size_t>(hi, 1, ts.size() - 1);
  const std::size_t lo = hi - 1;
  const double h = ts[hi] - ts[lo];
  const double s = (t - ts[lo]) / h;
  const double s2 = s * s, s3 = s2 * s;
  // Cubic Hermite basis and its derivative (per unit s).
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  const double d00 = 6 * s2 - 6 * s, d10 = 3 * s2 - 4 * s + 1, d01 = -6 * s2 + 6 * s, d11 = 3 * s2 - 2 * s;
  const Eigen::Vector3d& p0 = trajectory_.p[lo];
  const Eigen::Vector3d& p1 = trajectory_.p[hi];
  state.p_FM = h00 * p0 + h10 * h * v_[lo] + h01 * p1 + h11 * h * v_[hi];
  state.v_FM = (d00 * p0 + d01 * p1) / h + d10 * v_[lo] + d11 * v_[hi];
  state.R_FM = trajectory_.q[lo].slerp(s, trajectory_.q[hi]).toRotationMatrix();
  state.w_FM = (1 - s) * w_[lo] + s * w_[hi];
  return true;
}

bool ReferenceCurve::LinearPosition(double t, Eigen::Vector3d& p) const {
  Eigen::Quaterniond q;
  return InterpolatePose(trajectory_, t, p, q);
}

}  // namespace robossis::calibration
