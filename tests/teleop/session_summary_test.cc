// The summary's follower counts come from the records alone (so that a replayed log reproduces them): the
// set-points the follower refused, by reason, and the ticks at which the measured joints broke a limit.
#include "src/teleop/session_summary.h"

#include <cmath>

#include <gtest/gtest.h>

namespace robossis::teleop {
namespace {

TEST(SessionSummaryTest, CountsRefusedSetPointsByReasonFromTheRecords) {
  SessionSummary summary(SummaryOptions{});
  const SetPointVerdict verdicts[] = {SetPointVerdict::kAccepted, SetPointVerdict::kTooFast, SetPointVerdict::kStale,
                                      SetPointVerdict::kTooFast, SetPointVerdict::kAccepted};
  std::uint64_t tick = 0;
  for (SetPointVerdict v : verdicts) {
    for (int k = 0; k < 10; ++k) {  // one set-point per 10 follower ticks
      FollowerTickRecord r;
      r.tick = ++tick;
      r.time_s = 1e-4 * static_cast<double>(tick);
      r.took_setpoint = k == 0;
      r.setpoint_verdict = k == 0 ? v : SetPointVerdict::kAccepted;
      r.meas_feasible = !(v == SetPointVerdict::kStale && k == 3);
      summary.AddFollower(r);
    }
  }
  const auto s = summary.Summary();
  const auto& by = s.at("setpoints_rejected_by_reason");
  EXPECT_EQ(by.at("too_fast"), 2);
  EXPECT_EQ(by.at("stale"), 1);
  EXPECT_EQ(by.at("infeasible"), 0);
  EXPECT_FALSE(by.contains("accepted"));
  EXPECT_EQ(s.at("follower_limit_violations"), 1);
  EXPECT_EQ(s.at("follower_ticks"), 50);
}

TEST(SessionSummaryTest, TheFollowersSpeedIsMeasuredOverItsMeasurementsNotItsTicks) {
  // A back end that measures once per 1 ms step (the Bullet simulation) moving at exactly 10 mm/s, read by 10 kHz
  // ticks; one step in three lands a tick late, so a window of 100 ticks sometimes holds 11 steps of motion. Over
  // the ticks' times that window reads 11 mm/s; over the measurements' own times it is the true 10 mm/s.
  SessionSummary summary(SummaryOptions{});
  constexpr double kSpeed = 0.01;  // m/s
  int steps_done = 0;
  for (int tick = 1; tick <= 5000; ++tick) {
    // Step k (1, 2, ...) is due at tick 10k - 5, and steps 3, 6, 9, ... run one tick late.
    const int next = steps_done + 1;
    if (tick >= 10 * next - 5 + (next % 3 == 0 ? 1 : 0)) steps_done = next;
    FollowerTickRecord r;
    r.tick = static_cast<std::uint64_t>(tick);
    r.time_s = 1e-4 * tick;
    r.meas_time_s = 1e-3 * steps_done;
    r.meas_p_FM = {kSpeed * r.meas_time_s, 0, 0.284};
    summary.AddFollower(r);
  }
  const auto s = summary.Summary();
  EXPECT_NEAR(s.at("max_follower_speed_mm_s").get<double>(), 10.0, 1e-9);
}

TEST(SessionSummaryTest, AHugeValueStaysOneShortCell) {
  SessionSummary summary(SummaryOptions{});
  LeaderTickRecord r;
  r.q_OH = {1, 0, 0, 0};
  r.q_goal = r.q_sent = r.q_OH;
  r.f_O = {1e300, 0, 0};  // "%.4f" printed 301 digits before the point (and snprintf cut the rest at its buffer)
  summary.AddLeader(r);
  const std::string& csv = summary.leader_csv();
  const std::string row = csv.substr(csv.find('\n') + 1);
  EXPECT_NE(row.find(",1.0000000000000001e+300,"), std::string::npos) << row;
  EXPECT_LT(row.size(), 400u) << row;
}


// The summary's hand-to-set-point delay: leader records at 1 kHz whose set-point displacement is the ideal one
// delayed by 40 ms, with a Rebase (both displacements held at zero, as while the robot does not follow) in the
// middle. The delay is found; where eq. 11 capped the hand (scale < 1) on most ticks, the figure is null and the
// status says why; with no set-points at all, too few samples.
LeaderTickRecord DelayRecord(int k, double delay_s, bool rebased, double scale) {
  auto motion = [](double t) {
    return t <= 0 ? 0.0 : 0.004 * (1 - std::cos(2.1 * t)) + 0.0015 * (1 - std::cos(5.3 * t)) + 0.001 * t * t;
  };
  LeaderTickRecord r;
  r.t_ns = 1'000'000LL * k;
  r.sent_this_tick = 1;
  r.scale_linear = scale;
  const double t = 1e-3 * k;
  // After the rebase at 3 s (held until 3.2 s) both restart from zero.
  const double t0 = t >= 3.2 ? 3.2 : 0.0;
  if (!rebased) {
    r.ideal_disp[0] = motion(t) - motion(t0);
    r.transfer_disp[0] = motion(t - delay_s) - motion(t0 - delay_s);
  }
  return r;
}

TEST(SessionSummaryTest, TheHandToSetPointDelayRespectsResetsAndTheCap) {
  constexpr double kDelay = 0.040;
  SessionSummary ok(SummaryOptions{});
  SessionSummary capped(SummaryOptions{});
  for (int k = 0; k <= 6000; ++k) {
    const bool rebased = k >= 3000 && k < 3200;
    ok.AddLeader(DelayRecord(k, kDelay, rebased, 1.0));
    capped.AddLeader(DelayRecord(k, kDelay, rebased, k % 10 == 0 ? 1.0 : 0.5));  // capped 90 % of the time
  }
  const auto s = ok.Summary();
  ASSERT_EQ(s.at("hand_to_setpoint_delay_status"), "ok");
  EXPECT_NEAR(s.at("hand_to_setpoint_delay_ms").get<double>(), 1e3 * kDelay, 1.0);
  EXPECT_GT(s.at("hand_to_setpoint_delay_judged_fraction").get<double>(), 0.9);
  EXPECT_LT(s.at("hand_to_setpoint_delay_judged_fraction").get<double>(), 0.99);  // the rebased ticks are not judged

  const auto c = capped.Summary();
  EXPECT_TRUE(c.at("hand_to_setpoint_delay_ms").is_null());
  EXPECT_EQ(c.at("hand_to_setpoint_delay_status"), "cap_binds");

  const auto none = SessionSummary(SummaryOptions{}).Summary();
  EXPECT_TRUE(none.at("hand_to_setpoint_delay_ms").is_null());
  EXPECT_EQ(none.at("hand_to_setpoint_delay_status"), "too_few_samples");
  EXPECT_EQ(none.at("hand_to_setpoint_delay_judged_fraction"), 0.0);
}

}  // namespace
}  // namespace robossis::teleop
