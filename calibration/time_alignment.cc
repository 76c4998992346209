#include "calibration/time_alignment.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "src/core/pose.h"

namespace robossis::calibration {

namespace {

// Standardized speed signal on a uniform grid t0 + k·dt: linear speed and angular speed, each z-scored and summed.
struct Signal {
  double t0 = 0, dt = 0;
  std::vector<double> v;
};

Signal SpeedSignal(const PoseTrajectory& x, double dt) {
  Signal s;
  s.t0 = x.t_s.front();
  s.dt = dt;
  const std::size_t n = static_cast<std::size_t>(std::floor(x.duration_s() / dt));
  std::vector<double> lin(n), ang(n);
  Eigen::Vector3d p0, p1;
  Eigen::Quaterniond q0, q1;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = s.t0 + static_cast<double>(k) * dt;
    InterpolatePose(x, t, p0, q0);
    InterpolatePose(x, std::min(t + dt, x.t_s.back()), p1, q1);
    lin[k] = (p1 - p0).norm() / dt;
    ang[k] = q0.angularDistance(q1) / dt;
  }
  auto standardize = [](std::vector<double>& v) {
    double mean = 0, sq = 0;
    for (double a : v) mean += a;
    mean /= static_cast<double>(std::max<std::size_t>(v.size(), 1));
    for (double a : v) sq += (a - mean) * (a - mean);
    const double sd = std::sqrt(sq / static_cast<double>(std::max<std::size_t>(v.size(), 1)));
    for (double& a : v) a = sd > 0 ? (a - mean) / sd : 0.0;
  };
  standardize(lin);
  standardize(ang);
  s.v.resize(n);
  for (std::size_t k = 0; k < n; ++k) s.v[k] = lin[k] + ang[k];
  return s;
}

// Normalized correlation of a(t) and b(t - offset) over their overlap; -2 if the overlap is too short.
double Correlation(const Signal& a, const Signal& b, double offset_s, double min_overlap_s) {
  // a is the reference on its grid; b is sampled at t_ref - offset on the reference grid (nearest sample).
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  std::size_t count = 0;
  for (std::size_t k = 0; k < a.v.size(); ++k) {
    const double t_b = a.t0 + static_cast<double>(k) * a.dt - offset_s;
    const double u = (t_b - b.t0) / b.dt;
    if (u < 0 || u > static_cast<double>(b.v.size()) - 1) continue;
    const std::size_t j = static_cast<std::size_t>(u);
    const double f = u - static_cast<double>(j);
    const double vb = j + 1 < b.v.size() ? (1 - f) * b.v[j] + f * b.v[j + 1] : b.v[j];
    const double va = a.v[k];
    sa += va;
    sb += vb;
    saa += va * va;
    sbb += vb * vb;
    sab += va * vb;
    ++count;
  }
  if (static_cast<double>(count) * a.dt < min_overlap_s || count < 8) return -2;
  const double c = static_cast<double>(count);
  const double cov = sab / c - (sa / c) * (sb / c);
  const double va = saa / c - (sa / c) * (sa / c), vb = sbb / c - (sb / c) * (sb / c);
  if (va <= 0 || vb <= 0) return -2;
  return cov / std::sqrt(va * vb);
}

}  // namespace

SpeedCorrelationResult EstimateOffsetBySpeedCorrelation(const PoseTrajectory& reference, const PoseTrajectory& tracked,
                                                        const SpeedCorrelationOptions& options) {
  if (reference.size() < 4 || tracked.size() < 4) {
    throw std::runtime_error("time alignment: need at least 4 poses in each recording");
  }
  const double shorter = std::min(reference.duration_s(), tracked.duration_s());
  const double min_overlap = options.min_overlap_fraction * shorter;
  // offset range: t_ref = t_mocap + offset, with enough overlap.
  const double lo = reference.t_s.front() - tracked.t_s.back() + min_overlap;
  const double hi = reference.t_s.back() - tracked.t_s.front() - min_overlap;
  if (!(hi >= lo)) throw std::runtime_error("time alignment: the recordings are too short to overlap");
  // Coarse-to-fine: ~2000 candidate offsets at the first level, then ±20 steps around the best at each finer one.
  double step = std::max((hi - lo) / 2000.0, options.finest_step_s);
  double best = 0.5 * (lo + hi), best_c = -3;
  double a = lo, b = hi;
  for (int level = 0; level < 12; ++level) {
    // Signals sampled at the step (bounded to 200k samples), so their features match the search resolution.
    const double dt = std::max({step, shorter / 200000.0, 1e-4});
    const Signal sr = SpeedSignal(reference, dt);
    const Signal st = SpeedSignal(tracked, dt);
    if (sr.v.size() < 8 || st.v.size() < 8) break;
    double prev_c = -3;
    std::vector<double> cs;
    std::vector<double> offs;
    for (double off = a; off <= b + 1e-12; off += step) {
      const double c = Correlation(sr, st, off, min_overlap);
      offs.push_back(off);
      cs.push_back(c);
      (void)prev_c;
    }
    std::size_t k = 0;
    for (std::size_t i = 1; i < cs.size(); ++i) {
      if (cs[i] > cs[k]) k = i;
    }
    if (cs.empty() || cs[k] <= -2) throw std::runtime_error("time alignment: no overlapping motion to correlate");
    best = offs[k];
    best_c = cs[k];
    if (k > 0 && k + 1 < cs.size()) {  // parabolic peak
      const double d = cs[k - 1] - 2 * cs[k] + cs[k + 1];
      if (d < 0) best += 0.5 * step * (cs[k - 1] - cs[k + 1]) / d;
    }
    if (step <= options.finest_step_s * 1.0001) break;
    const double next = std::max(step / 10.0, options.finest_step_s);
    a = best - 20 * next;
    b = best + 20 * next;
    step = next;
  }
  if (!(best_c > 0.2)) {
    throw std::runtime_error("time alignment: the speed profiles do not match (best correlation " +
                             std::to_string(best_c) + "); is this the right command log for this take?");
  }
  return {best, best_c};
}

}  // namespace robossis::calibration
