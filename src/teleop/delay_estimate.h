#pragma once
// The hand-to-set-point delay of the motion transfer, estimated one way for every caller (the teleoperation
// summary and the off-line chain): the lag that best aligns the set-point's velocity with the velocity of the
// ideal incremental trajectory (the hand through eq. 10–11 alone, before any filter), delayed by that lag.
//
// Velocities, not positions, so that motion a stall discarded (a constant offset) does not bias the lag. The linear
// part is compared, unless the reference only turned (then the angular part). Not real-time (it allocates).

#include <cstddef>
#include <span>
#include <vector>

#include "src/core/pose.h"

namespace robossis::teleop {

// Fewer samples than this in either series: no estimate.
inline constexpr std::size_t kMinDelaySamples = 20;

struct DelaySearch {
  double max_lag_s = 0.5;    // lags searched: 0 .. max_lag_s
  double lag_step_s = 5e-4;  // in steps of lag_step_s
};

struct DelayEstimate {
  bool valid = false;        // false: too few samples, or no overlap between the series at any lag
  double delay_s = 0;
  double rms_residual = 0;   // the velocity RMS left at that lag (m/s, or rad/s when `angular`)
  bool angular = false;      // the angular part was compared (the reference only turned)
};

// Central differences of a displacement series [p; theta] sampled at increasing times `t` (one-sided at the ends).
std::vector<Vector6d> VelocityOf(std::span<const double> t, std::span<const Vector6d> x);

// `reference` is the ideal displacement at times `t_ref` (increasing); `velocity` the delayed series' velocity at
// times `t` (increasing). Each lag is judged on the samples of `velocity` whose time minus the lag lies within the
// reference; the reference velocity is linearly interpolated there.
DelayEstimate EstimateDelay(std::span<const double> t_ref, std::span<const Vector6d> reference,
                            std::span<const double> t, std::span<const Vector6d> velocity,
                            const DelaySearch& search = {});

}  // namespace robossis::teleop
