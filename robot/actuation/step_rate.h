#pragma once
// The step rate a pulse train reaches: the most steps of one motor within any window of kStepRateWindowS, divided by
// the window. The one computation of the figure (summary.json `max_step_rate_hz`, the demo report, the tests).
//
// The window is half-open, (t - W, t]: a train of exactly f steps per second then counts f · W steps in every
// window, so a 4000 Hz train reads 4000 Hz (a closed window [t - W, t] holds both ends and read 4100 Hz).

#include <vector>

#include "robot/actuation/pulse_generator.h"

namespace robossis::actuation {

// [assumed] 10 ms: long enough to average over a few steps at the lowest rates that matter (100 Hz is one step),
// short enough to see the peak of an eq. 9 move (a 1 s move's speed changes by < 2 % in 10 ms).
inline constexpr double kStepRateWindowS = 0.010;
// [assumed] Step times within this of a window's open end count as outside it: the times are sums of tick
// periods, so an exact train's steps land on the end up to rounding (~1e-16 s). 1 ns is far below any step
// spacing a drive can make (LinuxCNC's software stepgen resolves 50 µs, hal.yaml base_period_ns).
inline constexpr double kStepRateTimeToleranceS = 1e-9;

// The highest per-motor step rate (Hz) of `events` over windows of `window_s` (> 0). Events may interleave motors
// (each motor's steps in time order, as the actuator issues them). 0 for no events.
double MaxStepRateHz(const std::vector<StepEvent>& events, double window_s = kStepRateWindowS);

}  // namespace robossis::actuation
