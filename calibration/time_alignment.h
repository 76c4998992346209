#pragma once
// Clock alignment between a mocap recording and a command log: t_reference = (1 + drift) · t_mocap + offset.

#include "calibration/trajectory.h"

namespace robossis::calibration {

struct ClockModel {
  double offset_s = 0;
  double drift = 0;  // dimensionless rate error (1e-6 = 1 ppm)
  double ToReference(double t_mocap_s) const { return (1.0 + drift) * t_mocap_s + offset_s; }
};

struct SpeedCorrelationOptions {
  // Searched offsets: those where the overlap covers at least this fraction of the shorter recording.
  double min_overlap_fraction = 0.5;
  // The finest grid of the search (s). The result is refined to sub-sample precision by a parabola.
  double finest_step_s = 0.001;
  // Search only offsets within center_s ± half_width_s (a known approximate offset; needed when the motion
  // repeats itself, which makes the speed profiles match at several offsets).
  bool bounded = false;
  double center_s = 0, half_width_s = 2.0;
  // Speeds are taken over chords at least this long, so the tracker's noise does not swamp them (at 240 Hz and
  // 0.1 mm noise a one-frame difference has 34 mm/s of noise; over 50 ms, 2.8 mm/s). Assumption: 50 ms, short
  // against the motion's reversals (seconds) and ample for a start the fit refines.
  double speed_baseline_s = 0.05;
  // The command log's speeds vary by less than this (standard deviation / mean, linear and angular both): constant
  // speeds, nothing to correlate (constant_speed). Assumption: 5 %.
  double constant_speed_variation = 0.05;
};

struct SpeedCorrelationResult {
  double offset_s = 0;
  double correlation = 0;  // normalized cross-correlation at the peak, in [-1, 1]
  bool constant_speed = false;  // the speeds do not vary: offset_s is the search's centre (or 0), not an estimate
};

// Coarse-to-fine search for the offset maximizing the normalized cross-correlation of the speed profiles
// (angular speed and linear speed, each standardized), by the project's one lag estimator (src/core/lag_estimate.h).
// Angular speed does not depend on the unknown tracker transform or marker offset, which is why it is used before
// any registration. Throws std::runtime_error if the recordings are too short or do not match; constant speeds
// (nothing to correlate) give constant_speed.
SpeedCorrelationResult EstimateOffsetBySpeedCorrelation(const PoseTrajectory& reference,
                                                        const PoseTrajectory& tracked,
                                                        const SpeedCorrelationOptions& options = {});

}  // namespace robossis::calibration
