#include "src/teleop/delay_estimate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace robossis::teleop {

std::vector<Vector6d> VelocityOf(std::span<const double> t, std::span<const Vector6d> x) {
  const std::size_t n = std::min(t.size(), x.size());
  std::vector<Vector6d> v(n, Vector6d::Zero());
  if (n < 2) return v;
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t a = j == 0 ? 0 : j - 1, b = j + 1 == n ? j : j + 1;
    const double span = t[b] - t[a];
    if (span > 0) v[j] = (x[b] - x[a]) / span;
  }
  return v;
}

DelayEstimate EstimateDelay(std::span<const double> t_ref, std::span<const Vector6d> reference,
                            std::span<const double> t, std::span<const Vector6d> velocity,
                            const DelaySearch& search) {
  DelayEstimate out;
  const std::size_t n_ref = std::min(t_ref.size(), reference.size());
  const std::size_t n = std::min(t.size(), velocity.size());
  if (n_ref < kMinDelaySamples || n < kMinDelaySamples || !(search.lag_step_s > 0) || !(search.max_lag_s >= 0)) {
    return out;
  }
  const std::vector<Vector6d> v_ref = VelocityOf(t_ref.first(n_ref), reference.first(n_ref));
  double lin_range = 0, ang_range = 0;
  for (std::size_t j = 0; j < n_ref; ++j) {
    lin_range = std::max(lin_range, reference[j].head<3>().norm());
    ang_range = std::max(ang_range, reference[j].tail<3>().norm());
  }
  // The linear part unless the reference moved less than 1 mm and turned.
  out.angular = !(lin_range >= 1e-3 || ang_range == 0);
  const int off = out.angular ? 3 : 0;

  // The samples judged: those inside the reference's time span (the same set at every lag, so costs compare).
  std::vector<std::size_t> idx;
  for (std::size_t k = 0; k < n; ++k) {
    if (t[k] >= t_ref[0] && t[k] <= t_ref[n_ref - 1]) idx.push_back(k);
  }
  if (idx.empty()) return out;

  const int lags = static_cast<int>(std::floor(search.max_lag_s / search.lag_step_s + 1e-9));
  double best_cost = std::numeric_limits<double>::infinity();
  double best_lag = 0;
  for (int l = 0; l <= lags; ++l) {
    const double lag = l * search.lag_step_s;
    double cost = 0;
    std::size_t j = 0;  // t_ref[j] <= query < t_ref[j + 1]; the queries increase with k
    for (std::size_t k : idx) {
      const double q = t[k] - lag;
      Eigen::Vector3d v;
      if (q <= t_ref[0]) {
        v = v_ref[0].segment<3>(off);  // before the reference: held at its first value
      } else {
        while (j + 2 < n_ref && t_ref[j + 1] <= q) ++j;
        const double t0 = t_ref[j], t1 = t_ref[j + 1];
        const double f = t1 > t0 ? std::clamp((q - t0) / (t1 - t0), 0.0, 1.0) : 1.0;
        v = ((1 - f) * v_ref[j] + f * v_ref[j + 1]).segment<3>(off);
      }
      cost += (velocity[k].segment<3>(off) - v).squaredNorm();
    }
    if (cost < best_cost) {
      best_cost = cost;
      best_lag = lag;
    }
  }
  out.valid = true;
  out.delay_s = best_lag;
  out.rms_residual = std::sqrt(best_cost / static_cast<double>(idx.size()));
  return out;
}

}  // namespace robossis::teleop
