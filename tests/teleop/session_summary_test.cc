// The summary's follower counts come from the records alone (so that a replayed log reproduces them): the
// set-points the follower refused, by reason, and the ticks at which the measured joints broke a limit.
#include "src/teleop/session_summary.h"

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

}  // namespace
}  // namespace robossis::teleop
