#pragma once
// Step/direction pulses for one motor (paper eq. 17). The motor's commanded position in steps is
// s(t) = (q(t) - q_0) · steps_per_unit; the steps issued n(t) follow round(s(t)): one step each time s crosses a
// half-integer, in the direction of the crossing, stamped at the exact crossing time (s is linear within a tick, as
// eq. 16 integrates). Hence |n - s| <= 1/2 at every tick, and n is a function of s alone: nothing accumulates, so
// there is no drift however long the motion.
//
// eq. 17 as printed (pulse = 1 when sin(q) > 0) is a square wave whose phase is the motor position; its rising edges
// are the steps. Read literally with a separate direction line it double-counts a step at each reversal that
// happens between edges; placing the edge at the crossing of the commanded position keeps the count exact.

#include <cstdint>

namespace robossis::actuation {

struct StepEvent {
  double time_s = 0;
  std::int8_t motor = 0;
  std::int8_t direction = 0;  // +1 or -1: the DIR line during this step
};

class PulseGenerator {
 public:
  PulseGenerator() = default;
  explicit PulseGenerator(double steps_per_unit) : steps_per_unit_(steps_per_unit) {}

  // Advances from the previous commanded displacement to `displacement` (joint units from q_0) over
  // [t_prev, t_now]; writes up to `capacity` step events (motor index `motor`) to `events` and returns the count.
  // Steps beyond the capacity wait for the next tick (the actuator's rate limit keeps that from happening).
  int Advance(double t_prev, double t_now, double displacement, int motor, StepEvent* events, int capacity) noexcept;

  std::int64_t steps() const { return steps_; }  // n: signed steps issued since the start
  double commanded_steps() const { return s_; }  // s
  int direction() const { return direction_; }

 private:
  double steps_per_unit_ = 1;
  double s_ = 0;
  std::int64_t steps_ = 0;
  int direction_ = 1;
};

}  // namespace robossis::actuation
