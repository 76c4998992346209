// eq. 17 pulses: the steps issued equal the commanded displacement within half a step at every tick, through
// direction changes, with no drift over an hour.

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "robot/actuation/pulse_generator.h"

namespace robossis::actuation {
namespace {

TEST(PulseGeneratorTest, StepsTrackTheCommandThroughDirectionChanges) {
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PulseGenerator pg(200.0 / 1e-3);  // 200 steps per mm (in m)
  std::array<StepEvent, 8> ev{};
  double x = 0, t = 0;
  std::int64_t net = 0;
  for (int k = 0; k < 200000; ++k) {
    x += 2e-6 * u(gen);  // up to 0.4 step per tick, reversing at random
    const int n = pg.Advance(t, t + 1e-4, x, 3, ev.data(), 8);
    for (int i = 0; i < n; ++i) {
      ASSERT_GE(ev[i].time_s, t);
      ASSERT_LE(ev[i].time_s, t + 1e-4);
      ASSERT_EQ(ev[i].motor, 3);
      net += ev[i].direction;
    }
    t += 1e-4;
    ASSERT_LE(std::abs(static_cast<double>(pg.steps()) - x * 200.0 / 1e-3), 0.5 + 1e-9) << "tick " << k;
    ASSERT_EQ(net, pg.steps());
  }
}

TEST(PulseGeneratorTest, StepTimesAreTheExactCrossings) {
  PulseGenerator pg(1.0);
  std::array<StepEvent, 8> ev{};
  // From 0 to 3 steps over one tick [0, 1]: crossings at 0.5, 1.5, 2.5 -> times 1/6, 1/2, 5/6.
  ASSERT_EQ(pg.Advance(0.0, 1.0, 3.0, 0, ev.data(), 8), 3);
  EXPECT_NEAR(ev[0].time_s, 1.0 / 6, 1e-15);
  EXPECT_NEAR(ev[1].time_s, 0.5, 1e-15);
  EXPECT_NEAR(ev[2].time_s, 5.0 / 6, 1e-15);
  // Back down to 1.2: crossings at 2.5 and 1.5, direction -1.
  ASSERT_EQ(pg.Advance(1.0, 2.0, 1.2, 0, ev.data(), 8), 2);
  EXPECT_EQ(ev[0].direction, -1);
  EXPECT_NEAR(ev[0].time_s, 1.0 + 0.5 / 1.8, 1e-15);
  EXPECT_EQ(pg.steps(), 1);
}

TEST(PulseGeneratorTest, NoDriftOverAnHourAtTenKilohertz) {
  // One hour of a back-and-forth stroke (±20 mm at 0.05 Hz plus a 1 Hz ripple), 36 million ticks.
  PulseGenerator pg(200.0 / 1e-3);
  std::array<StepEvent, 8> ev{};
  const double dt = 1e-4;
  const long ticks = 36'000'000;
  std::int64_t net = 0;
  double worst = 0;
  // The two sines advance by rotation recurrences (cheap; renormalised), not std::sin per tick.
  const double w1 = 2 * M_PI * 0.05 * dt, w2 = 2 * M_PI * 1.0 * dt;
  const double c1 = std::cos(w1), s1 = std::sin(w1), c2 = std::cos(w2), s2 = std::sin(w2);
  double a_c = 1, a_s = 0, b_c = 1, b_s = 0;
  for (long k = 1; k <= ticks; ++k) {
    const double t = k * dt;
    const double na = a_c * s1 + a_s * c1, nb = b_c * s2 + b_s * c2;
    a_c = a_c * c1 - a_s * s1;
    a_s = na;
    b_c = b_c * c2 - b_s * s2;
    b_s = nb;
    if ((k & 4095) == 0) {
      const double ra = std::hypot(a_c, a_s), rb = std::hypot(b_c, b_s);
      a_c /= ra, a_s /= ra, b_c /= rb, b_s /= rb;
    }
    const double x = 0.020 * a_s + 0.0005 * b_s + 1e-9 * k;
    const int n = pg.Advance(t - dt, t, x, 0, ev.data(), 8);
    for (int i = 0; i < n; ++i) net += ev[i].direction;
    if ((k & 1023) == 0) worst = std::max(worst, std::abs(pg.steps() - pg.commanded_steps()));
  }
  EXPECT_LE(worst, 0.5);
  EXPECT_EQ(net, pg.steps());
  EXPECT_LE(std::abs(pg.steps() - pg.commanded_steps()), 0.5);  // still exact after an hour
}

}  // namespace
}  // namespace robossis::actuation
