// The step-rate figure over a half-open window: an exact pulse train reads its own rate, not one step more.

#include <cstdint>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "robot/actuation/step_rate.h"

namespace robossis::actuation {
namespace {

std::vector<StepEvent> Train(int motor, double rate_hz, double duration_s, bool accumulate) {
  std::vector<StepEvent> events;
  double t = 0;
  for (int k = 0; k * (1.0 / rate_hz) <= duration_s + 1e-12; ++k) {
    StepEvent e;
    e.time_s = accumulate ? t : k / rate_hz;  // a sum of periods carries rounding, k / rate less
    e.motor = static_cast<std::int8_t>(motor);
    e.direction = 1;
    events.push_back(e);
    t += 1.0 / rate_hz;
  }
  return events;
}

TEST(StepRateTest, AnExact4000HzTrainReads4000Hz) {
  for (const bool accumulate : {false, true}) {
    // 1 s of steps every 250 µs: every 10 ms window (t - 10 ms, t] holds exactly 40 of them.
    EXPECT_DOUBLE_EQ(MaxStepRateHz(Train(3, 4000, 1.0, accumulate)), 4000.0) << accumulate;
    EXPECT_DOUBLE_EQ(MaxStepRateHz(Train(0, 1000, 0.5, accumulate)), 1000.0) << accumulate;
  }
}

TEST(StepRateTest, TheWindowIsHalfOpen) {
  const auto at = [](std::vector<double> times) {
    std::vector<StepEvent> events;
    for (double t : times) events.push_back(StepEvent{t, 1, 1});
    return events;
  };
  EXPECT_DOUBLE_EQ(MaxStepRateHz(at({0.0, 0.010})), 100.0);            // 10 ms apart: never in one window
  EXPECT_DOUBLE_EQ(MaxStepRateHz(at({0.0, 0.0099})), 200.0);           // just inside
  EXPECT_DOUBLE_EQ(MaxStepRateHz(at({0.0, 0.005, 0.0099, 0.0199})), 300.0);
  EXPECT_DOUBLE_EQ(MaxStepRateHz({}), 0.0);
}

TEST(StepRateTest, MotorsAreCountedApartAndTheFastestIsReported) {
  std::vector<StepEvent> events = Train(0, 2000, 0.2, false);
  const std::vector<StepEvent> fast = Train(5, 3000, 0.2, false);
  // Interleaved as the actuator issues them (tick by tick, motor order within a tick): each motor's own order kept.
  std::vector<StepEvent> mixed;
  std::size_t i = 0, j = 0;
  while (i < events.size() || j < fast.size()) {
    if (j == fast.size() || (i < events.size() && events[i].time_s <= fast[j].time_s)) {
      mixed.push_back(events[i++]);
    } else {
      mixed.push_back(fast[j++]);
    }
  }
  EXPECT_DOUBLE_EQ(MaxStepRateHz(mixed), 3000.0);
  // Two motors at 2000 Hz each are not one motor at 4000 Hz.
  std::vector<StepEvent> two = Train(1, 2000, 0.2, false);
  const std::vector<StepEvent> other = Train(2, 2000, 0.2, false);
  two.insert(two.end(), other.begin(), other.end());
  EXPECT_DOUBLE_EQ(MaxStepRateHz(two), 2000.0);
}

TEST(StepRateTest, OtherWindowsAndABadOne) {
  EXPECT_DOUBLE_EQ(MaxStepRateHz(Train(2, 4000, 1.0, true), 0.1), 4000.0);
  EXPECT_THROW(MaxStepRateHz(Train(2, 4000, 1.0, true), 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace robossis::actuation
