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
  // Mean speeds over bins of width dt: each step between native samples adds its path length (and rotation angle)
  // to the bin holding its midpoint. Averaging, not point sampling, so a coarse grid does not alias fast motion.
  Signal s;
  s.t0 = x.t_s.front();
  s.dt = dt;
  const std::size_t n = static_cast<std::size_t>(std::floor(x.duration_s() / dt));
  std::vector<double> lin(n, 0.0), ang(n, 0.0);
  for (std::size_t i = 0; i + 1 < x.size(); ++i) {
    const double mid = 0.5 * (x.t_s[i] + x.t_s[i + 1]);
    const std::size_t k = static_cast<std::size_t>((mid - s.t0) / dt);
    if (k >= n) continue;
    lin[k] += (x.p[i + 1] - x.p[i]).norm();
    ang[k] += x.q[i].angularDistance(x.q[i + 1]);
  }
  for (std::size_t k = 0; k < n; ++k) {
    lin[k] /= dt;
    ang[k] /= dt;
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
  double lo = reference.t_s.front() - tracked.t_s.back() + min_overlap;
  double hi = reference.t_s.back() - tracked.t_s.front() - min_overlap;
  if (options.bounded) {
    lo = std::max(lo, options.center_s - options.half_width_s);
    hi = std::min(hi, options.center_s + options.half_width_s);
  }
  if (!(hi >= lo)) throw std::runtime_error("time alignment: the recordings are too short to overlap");
  // Coarse-to-fine. Each level bins the speeds at dt and tries offsets every dt/4 (a peak can fall between
  // bins); the next level bins 10× finer around the best offset. Bins are never finer than twice the coarser
  // recording's mean sample interval (a bin must hold a sample step); the last level's parabolic peak gives the
  // sub-step offset, and the clock refinement after registration does the rest.
  const double native_dt = std::max(reference.duration_s() / static_cast<double>(reference.size() - 1),
                                    tracked.duration_s() / static_cast<double>(tracked.size() - 1));
  const double finest_dt = std::max({2.0 * native_dt, shorter / 200000.0, 1e-4});
  // One level: offsets in [a, b] every dt/4 on speeds binned at dt; returns all candidates.
  auto scan = [&](double dt, double a, double b, std::vector<double>& offs, std::vector<double>& cs) {
    offs.clear();
    cs.clear();
    const Signal sr = SpeedSignal(reference, dt);
    const Signal st = SpeedSignal(tracked, dt);
    if (sr.v.size() < 8 || st.v.size() < 8) return false;
    const double step = std::max(dt / 4.0, options.finest_step_s);
    for (double off = a; off <= b + 1e-12; off += step) {
      offs.push_back(off);
      cs.push_back(Correlation(sr, st, off, min_overlap));
    }
    return !cs.empty();
  };
  auto peak = [](const std::vector<double>& offs, const std::vector<double>& cs, std::size_t k) {
    double best = offs[k];
    if (k > 0 && k + 1 < cs.size()) {  // parabolic peak
      const double d = cs[k - 1] - 2 * cs[k] + cs[k + 1];
      if (d < 0) best += 0.5 * (offs[1] - offs[0]) * (cs[k - 1] - cs[k + 1]) / d;
    }
    return best;
  };
  const double dt0 = std::max((hi - lo) / 2000.0, finest_dt);
  std::vector<double> offs, cs;
  if (!scan(dt0, lo, hi, offs, cs)) throw std::runtime_error("time alignment: the recordings are too short");
  // The five highest local maxima of the coarse scan are refined: with coarse bins the true peak may rank below
  // a near-repeat of the motion.
  std::vector<std::size_t> maxima;
  for (std::size_t i = 0; i < cs.size(); ++i) {
    const bool left = i == 0 || cs[i] >= cs[i - 1], right = i + 1 == cs.size() || cs[i] >= cs[i + 1];
    if (left && right && cs[i] > -2) maxima.push_back(i);
  }
  if (maxima.empty()) throw std::runtime_error("time alignment: no overlapping motion to correlate");
  std::sort(maxima.begin(), maxima.end(), [&](std::size_t x, std::size_t y) { return cs[x] > cs[y]; });
  maxima.resize(std::min<std::size_t>(maxima.size(), 5));
  // Each candidate is refined one level; the best of them is refined down to the finest bins.
  auto refine = [&](double candidate, double dt, double& c_out) {
    const double next = std::max(dt / 10.0, finest_dt);
    std::vector<double> o2, c2;
    if (!scan(next, candidate - 2 * dt, candidate + 2 * dt, o2, c2)) return candidate;
    const std::size_t k = static_cast<std::size_t>(std::max_element(c2.begin(), c2.end()) - c2.begin());
    if (c2[k] <= -2) return candidate;
    c_out = c2[k];
    return peak(o2, c2, k);
  };
  double best = peak(offs, cs, maxima[0]), best_c = cs[maxima[0]];
  double dt = dt0;
  if (dt0 > finest_dt * 1.0001) {
    best_c = -3;
    for (std::size_t m : maxima) {
      double c = cs[m];
      const double candidate = refine(peak(offs, cs, m), dt0, c);
      if (c > best_c) {
        best = candidate;
        best_c = c;
      }
    }
    dt = std::max(dt0 / 10.0, finest_dt);
  }
  while (dt > finest_dt * 1.0001) {
    best = refine(best, dt, best_c);
    dt = std::max(dt / 10.0, finest_dt);
  }
  if (!(best_c > 0.2)) {
    throw std::runtime_error("time alignment: the speed profiles do not match (best correlation " +
                             std::to_string(best_c) + "); is this the right command log for this take?");
  }
  return {best, best_c};
}

}  // namespace robossis::calibration
