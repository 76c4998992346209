#include "robot/actuation/pulse_generator.h"

#include <cmath>

namespace robossis::actuation {

int PulseGenerator::Advance(double t_prev, double t_now, double displacement, int motor, StepEvent* events,
                            int capacity) noexcept {
  const double s_prev = s_;
  const double s_now = displacement * steps_per_unit_;
  s_ = s_now;
  // eq. 17: the target count is the nearest integer to s (half-integers round up).
  const std::int64_t target = static_cast<std::int64_t>(std::floor(s_now + 0.5));
  const double ds = s_now - s_prev;
  int count = 0;
  while (steps_ != target && count < capacity) {
    const int dir = target > steps_ ? 1 : -1;
    // The half-integer crossed: n + 1/2 going up, n - 1/2 going down.
    const double crossing = static_cast<double>(steps_) + 0.5 * dir;
    double f = ds != 0 ? (crossing - s_prev) / ds : 1.0;
    f = f < 0 ? 0 : (f > 1 ? 1 : f);
    events[count].time_s = t_prev + f * (t_now - t_prev);
    events[count].motor = static_cast<std::int8_t>(motor);
    events[count].direction = static_cast<std::int8_t>(dir);
    direction_ = dir;
    steps_ += dir;
    ++count;
  }
  return count;
}

}  // namespace robossis::actuation
