#include "calibration/time_alignment.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "src/core/lag_estimate.h"
#include "src/core/pose.h"

namespace robossis::calibration {

SpeedCorrelationResult EstimateOffsetBySpeedCorrelation(const PoseTrajectory& reference, const PoseTrajectory& tracked,
                                                        const SpeedCorrelationOptions& options) {
  if (reference.size() < 4 || tracked.size() < 4) {
    throw std::runtime_error("time alignment: need at least 4 poses in each recording");
  }
  // The speed profiles: linear and angular speed over chords of at least options.speed_baseline_s (the next
  // native sample when it is further), at the chord's midpoint. Angular speed does not depend on the unknown tracker
  // transform or marker offset (used before registration).
  struct Speeds {
    std::vector<double> t, v;  // v: [linear, angular] per chord
  };
  auto speeds = [&options](const PoseTrajectory& x) {
    Speeds s;
    std::size_t j = 1;
    for (std::size_t i = 0; i + 1 < x.size(); ++i) {
      j = std::max(j, i + 1);
      while (j + 1 < x.size() && x.t_s[j] - x.t_s[i] < options.speed_baseline_s) ++j;
      const double dt = x.t_s[j] - x.t_s[i];
      if (!(dt > 0)) continue;
      s.t.push_back(0.5 * (x.t_s[i] + x.t_s[j]));
      s.v.push_back((x.p[j] - x.p[i]).norm() / dt);
      s.v.push_back(x.q[i].angularDistance(x.q[j]) / dt);
    }
    return s;
  };
  Speeds sr = speeds(reference), st = speeds(tracked);
  // A few wild chords (an orientation flip of the tracker is a half turn in one frame) must not outweigh the
  // motion: each channel is clipped at kSpeedClipFactor times its 95th percentile (assumption: flips and outliers
  // are under 5 % of the chords).
  constexpr double kSpeedClipFactor = 2.0;
  for (Speeds* x : {&sr, &st}) {
    for (std::size_t c = 0; c < 2 && !x->t.empty(); ++c) {
      std::vector<double> v;
      for (std::size_t k = 0; k < x->t.size(); ++k) v.push_back(x->v[2 * k + c]);
      const std::size_t at = static_cast<std::size_t>(0.95 * static_cast<double>(v.size() - 1));
      std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(at), v.end());
      const double clip = kSpeedClipFactor * v[at];
      for (std::size_t k = 0; k < x->t.size(); ++k) x->v[2 * k + c] = std::min(x->v[2 * k + c], clip);
    }
  }
  // Constant speeds in the command log (a ring standing still, or turning at a constant rate): nothing to correlate,
  // and the tracker's noise would make any match a chance one. The fit starts from the approximate offset (or 0) and
  // reports the offset as not identifiable rather than failing here.
  {
    double cv[2];
    for (int c = 0; c < 2; ++c) {
      double sum = 0, sq = 0;
      const double n = static_cast<double>(sr.t.size());
      for (std::size_t k = 0; k < sr.t.size(); ++k) {
        sum += sr.v[2 * k + c];
        sq += sr.v[2 * k + c] * sr.v[2 * k + c];
      }
      const double mean = sum / n, var = std::max(0.0, sq / n - mean * mean);
      cv[c] = mean > 0 ? std::sqrt(var) / mean : 0.0;
    }
    if (!sr.t.empty() && cv[0] < options.constant_speed_variation && cv[1] < options.constant_speed_variation) {
      return {options.bounded ? options.center_s : 0.0, 0.0, true};
    }
  }
  // The one lag estimator (src/core/lag_estimate.h): the command log's reference trails the mocap by the offset,
  // t_reference = t_mocap + offset.
  LagSearchOptions search;
  search.min_overlap_fraction = options.min_overlap_fraction;
  search.finest_step_s = options.finest_step_s;
  if (options.bounded) {
    search.min_lag_s = options.center_s - options.half_width_s;
    search.max_lag_s = options.center_s + options.half_width_s;
  }
  const LagEstimate e = EstimateLag({.t_s = st.t, .values = st.v, .channels = 2},
                                    {.t_s = sr.t, .values = sr.v, .channels = 2}, search);
  switch (e.status) {
    case LagStatus::kOk: break;
    case LagStatus::kNoOverlap: throw std::runtime_error("time alignment: the recordings are too short to overlap");
    case LagStatus::kTooFewSamples: throw std::runtime_error("time alignment: the recordings are too short");
    case LagStatus::kNoMotion: return {options.bounded ? options.center_s : 0.0, 0.0, true};
    case LagStatus::kNoMatch:
      throw std::runtime_error("time alignment: the speed profiles do not match (best correlation " +
                               std::to_string(e.correlation) + "); is this the right command log for this take?");
  }
  return {e.lag_s, e.correlation};
}

}  // namespace robossis::calibration
