#include "calibration/time_alignment.h"

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
  // The speed profiles: linear and angular speed of each step between native samples, at the step's midpoint.
  // Angular speed does not depend on the unknown tracker transform or marker offset (used before registration).
  struct Speeds {
    std::vector<double> t, v;  // v: [linear, angular] per step
  };
  auto speeds = [](const PoseTrajectory& x) {
    Speeds s;
    for (std::size_t i = 0; i + 1 < x.size(); ++i) {
      const double dt = x.t_s[i + 1] - x.t_s[i];
      if (!(dt > 0)) continue;
      s.t.push_back(0.5 * (x.t_s[i] + x.t_s[i + 1]));
      s.v.push_back((x.p[i + 1] - x.p[i]).norm() / dt);
      s.v.push_back(x.q[i].angularDistance(x.q[i + 1]) / dt);
    }
    return s;
  };
  const Speeds sr = speeds(reference), st = speeds(tracked);
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
    case LagStatus::kNoMotion: throw std::runtime_error("time alignment: no overlapping motion to correlate");
    case LagStatus::kNoMatch:
      throw std::runtime_error("time alignment: the speed profiles do not match (best correlation " +
                               std::to_string(e.correlation) + "); is this the right command log for this take?");
  }
  return {e.lag_s, e.correlation};
}

}  // namespace robossis::calibration
