// The summary's follower counts come from the records alone (so that a replayed log reproduces them): the
// set-points the follower refused, by reason, and the ticks at which the measured joints broke a limit.
#include "src/teleop/session_summary.h"

#include <cmath>
#include <string>
#include <vector>

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

// position_drift_mm is the follower's offset from the path of its set-points, not its lag behind the newest one: a
// follower 40 ms behind set-points moving at 100 mm/s (4 mm behind the newest) that stays on their path drifts 0;
// one also 0.3 mm off that path drifts 0.3 mm. As the distance to the newest set-point at the end, the first read
// 4 mm, so this test can fail.
TEST(SessionSummaryTest, TheDriftIsTheOffsetFromTheSetPointsPathNotTheLag) {
  for (const double offset_m : {0.0, 3e-4}) {
    SCOPED_TRACE(offset_m);
    SessionSummary summary(SummaryOptions{});
    constexpr double kSpeed = 0.1, kLagS = 0.04;
    for (int tick = 1; tick <= 20000; ++tick) {  // 2 s at 10 kHz, a set-point every 10 ticks
      FollowerTickRecord r;
      r.tick = static_cast<std::uint64_t>(tick);
      r.time_s = 1e-4 * tick;
      r.meas_time_s = r.time_s;
      r.state = OperatingState::kEnabled;
      r.setpoint_sequence = static_cast<std::uint64_t>(tick / 10);
      const double t_sent = 1e-3 * static_cast<double>(r.setpoint_sequence);
      r.setpoint_p_FM = {kSpeed * t_sent, 0, 0.284};
      r.meas_p_FM = {kSpeed * std::max(0.0, r.time_s - kLagS), offset_m, 0.284};
      summary.AddFollower(r);
    }
    const auto s = summary.Summary();
    EXPECT_NEAR(s.at("position_drift_mm").get<double>(), 1e3 * offset_m, 1e-6);
    EXPECT_LE(s.at("position_drift_max_mm").get<double>(), 1e3 * offset_m + 1e-6);
  }
}

// feedback_force_error_n_rms judges the load shown against the follower's TRUE load, mapped into the device frame
// (gain, scale, R_FOᵀ) at the time of the status the leader showed (the link's delay removed), not against the
// estimate it received: here the estimate is 2 N off and the shown force is exactly the true load 50 ms (the link's
// delay) earlier, which a comparison at the leader's own time would miss by the load's change.
TEST(SessionSummaryTest, TheShownLoadIsJudgedAgainstTheTrueLoadWithTheDelayRemoved) {
  SummaryOptions options;
  options.feedback_map_known = true;
  options.feedback_gain = 0.025;
  options.feedback_translation_scale = 2;
  options.feedback_R_FO = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d M = 0.025 * 2 * options.feedback_R_FO.transpose();
  SessionSummary summary(options);
  const auto true_force = [](double t) { return Eigen::Vector3d(300 + 1000 * t, -50, 100 * t); };
  for (int k = 0; k <= 20000; ++k) {  // 2 s of follower ticks at 10 kHz
    FollowerTickRecord f;
    f.time_s = 1e-4 * k;
    f.true_load_known = true;
    const Eigen::Vector3d W = true_force(f.time_s);
    for (int i = 0; i < 3; ++i) f.true_wrench_F[i] = W[i];
    summary.AddFollower(f);
  }
  for (int k = 100; k < 2000; ++k) {  // the leader at 1 kHz, showing the status stamped 50 ms earlier
    LeaderTickRecord l;
    l.t_ns = 1'000'000LL * k;
    l.follower_stamp_ns = l.t_ns - 50'000'000;
    l.feedback_shown = 1;
    const Eigen::Vector3d shown = M * true_force(1e-9 * static_cast<double>(l.follower_stamp_ns));
    for (int i = 0; i < 3; ++i) {
      l.feedback_O[i] = shown[i];
      l.feedback_wanted_O[i] = shown[i] + (i == 0 ? 2.0 : 0.0);  // the estimate, 2 N off
    }
    summary.AddLeader(l);
  }
  const auto j = summary.Summary();
  EXPECT_LT(j["feedback_force_error_n_rms"].get<double>(), 1e-9);
  EXPECT_NEAR(j["feedback_force_error_vs_estimate_n_rms"].get<double>(), 2.0, 1e-9);
  // Not known (hardware, or a log without the map): not judged.
  SessionSummary unknown(SummaryOptions{});
  EXPECT_TRUE(unknown.Summary()["feedback_force_error_n_rms"].is_null());
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
// middle. The delay is found; where eq. 11 capped the hand (scale < 1) on most ticks, or the leader held the
// set-point sent back from the transfer's on most ticks (a wall, the motors' speeds), the figure is null and the
// status says why; with no set-points at all, too few samples.
LeaderTickRecord DelayRecord(int k, double delay_s, bool rebased, double scale, bool held_back = false) {
  auto motion = [](double t) {
    return t <= 0 ? 0.0 : 0.004 * (1 - std::cos(2.1 * t)) + 0.0015 * (1 - std::cos(5.3 * t)) + 0.001 * t * t;
  };
  LeaderTickRecord r;
  r.t_ns = 1'000'000LL * k;
  r.sent_this_tick = 1;
  r.scale_linear = scale;
  // The transfer asks for a pose 1 mm from the one sent (the poses are otherwise irrelevant here).
  if (held_back) r.p_goal[0] = 1e-3;
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
  SessionSummary held(SummaryOptions{});
  SessionSummary held_rarely(SummaryOptions{});
  for (int k = 0; k <= 6000; ++k) {
    const bool rebased = k >= 3000 && k < 3200;
    ok.AddLeader(DelayRecord(k, kDelay, rebased, 1.0));
    capped.AddLeader(DelayRecord(k, kDelay, rebased, k % 10 == 0 ? 1.0 : 0.5));  // capped 90 % of the time
    held.AddLeader(DelayRecord(k, kDelay, rebased, 1.0, k % 10 != 0));           // held back 90 % of the time
    held_rarely.AddLeader(DelayRecord(k, kDelay, rebased, 1.0, k >= 5500));      // the last 0.5 s only
  }
  const auto s = ok.Summary();
  ASSERT_EQ(s.at("hand_to_setpoint_delay_status"), "ok");
  EXPECT_NEAR(s.at("hand_to_setpoint_delay_ms").get<double>(), 1e3 * kDelay, 1.0);
  EXPECT_GT(s.at("hand_to_setpoint_delay_judged_fraction").get<double>(), 0.9);
  EXPECT_LT(s.at("hand_to_setpoint_delay_judged_fraction").get<double>(), 0.99);  // the rebased ticks are not judged

  const auto c = capped.Summary();
  EXPECT_TRUE(c.at("hand_to_setpoint_delay_ms").is_null());
  EXPECT_EQ(c.at("hand_to_setpoint_delay_status"), "cap_binds");

  const auto h = held.Summary();
  EXPECT_TRUE(h.at("hand_to_setpoint_delay_ms").is_null());
  EXPECT_EQ(h.at("hand_to_setpoint_delay_status"), "cap_binds");
  const auto hr = held_rarely.Summary();
  ASSERT_EQ(hr.at("hand_to_setpoint_delay_status"), "ok");
  EXPECT_NEAR(hr.at("hand_to_setpoint_delay_ms").get<double>(), 1e3 * kDelay, 1.0);
  EXPECT_LT(hr.at("hand_to_setpoint_delay_judged_fraction").get<double>(),
            s.at("hand_to_setpoint_delay_judged_fraction").get<double>() - 0.05);  // the held ticks are not judged

  const auto none = SessionSummary(SummaryOptions{}).Summary();
  EXPECT_TRUE(none.at("hand_to_setpoint_delay_ms").is_null());
  EXPECT_EQ(none.at("hand_to_setpoint_delay_status"), "too_few_samples");
  EXPECT_EQ(none.at("hand_to_setpoint_delay_judged_fraction"), 0.0);
}


// The run's verdict: a follower stream of 10 kHz ticks, one set-point per 10 ticks while the leader sends, as the
// follower records it. `events` change the state at given ticks; set-points stop over [gap_from, gap_to).
struct FollowerRun {
  struct Event {
    int tick;
    OperatingState state;
    FaultReason reason = FaultReason::kNone;
  };
  std::vector<Event> events;
  int ticks = 20000;
  int gap_from = -1, gap_to = -1;
  int sends_until = 20000;                                  // the leader's last set-point (its run's end)
  std::uint8_t flags = kSetPointPresence;                   // the newest set-point's flags
  int flags_from = -1;                                      // ... and from this tick, `later_flags`
  std::uint8_t later_flags = 0;
  bool complete = true;

  SessionSummary Summarise() const {
    SessionSummary summary(SummaryOptions{});
    OperatingState state = OperatingState::kReady;
    FaultReason reason = FaultReason::kNone;
    std::size_t next = 0;
    for (int tick = 0; tick < ticks; ++tick) {
      while (next < events.size() && events[next].tick == tick) {
        state = events[next].state;
        reason = events[next].reason;
        ++next;
      }
      FollowerTickRecord r;
      r.tick = static_cast<std::uint64_t>(tick);
      r.time_s = 1e-4 * tick;
      r.state = state;
      r.reason = reason;
      r.setpoint_flags = flags_from >= 0 && tick >= flags_from ? later_flags : flags;
      r.took_setpoint = tick % 10 == 0 && tick < sends_until && !(tick >= gap_from && tick < gap_to);
      summary.AddFollower(r);
    }
    if (complete) summary.SetEnd(SessionEndRecord{});
    return summary;
  }
};

// Following from tick 100, held at `hold`, the leader declared lost at `lost`; `ticks` in all.
FollowerRun HeldThenLeaderLost(int hold, int lost, int ticks) {
  FollowerRun run;
  run.events = {{100, OperatingState::kEnabled},
                {hold, OperatingState::kReady},
                {lost, OperatingState::kDisabled, FaultReason::kLeaderLost}};
  run.ticks = ticks;
  run.sends_until = ticks;
  return run;
}

TEST(RunVerdictTest, ALeaderLostWhileTheLeaderStillSendsIsNotClean) {
  // The leader's loop stalled 759 ms at 7.44 s: the follower held after 30 ms, declared the leader lost after 500 ms
  // and stayed disabled, while the set-points came back.
  FollowerRun run = HeldThenLeaderLost(74700, 79400, 170000);
  run.gap_from = 74400;
  run.gap_to = 82000;
  const SessionSummary summary = run.Summarise();
  const RunVerdict v = summary.Verdict();
  EXPECT_TRUE(v.judged);
  EXPECT_FALSE(v.clean);
  EXPECT_EQ(v.faults, 1u);
  EXPECT_EQ(v.reason, "leader_lost");
  EXPECT_NEAR(v.t_s, 7.47, 1e-9);  // when it stopped following: the hold
  EXPECT_NE(v.description.find("the leader declared lost"), std::string::npos) << v.description;
  EXPECT_NE(v.description.find("did not follow again"), std::string::npos) << v.description;
  // summary.json says the same, and reads back.
  const auto s = summary.Summary();
  EXPECT_EQ(s.at("run_clean"), false);
  EXPECT_EQ(s.at("run_fault").at("reason"), "leader_lost");
  const RunVerdict back = ReadRunVerdict(s);
  EXPECT_FALSE(back.clean);
  EXPECT_EQ(back.description, v.description);
}

TEST(RunVerdictTest, AWatchdogHoldThatFollowingResumesFromIsCountedAndOneThatNeverEndsIsNotClean) {
  FollowerRun run;
  run.events = {{100, OperatingState::kEnabled}, {5300, OperatingState::kReady}, {5400, OperatingState::kEnabled}};
  run.gap_from = 5000;
  run.gap_to = 5400;
  const SessionSummary resumed = run.Summarise();
  const RunVerdict v = resumed.Verdict();
  EXPECT_TRUE(v.clean);
  EXPECT_EQ(v.holds, 1u);
  EXPECT_NEAR(v.hold_s, 0.01, 1e-9);
  const auto s = resumed.Summary();
  EXPECT_EQ(s.at("run_holds"), 1u);
  EXPECT_EQ(ReadRunVerdict(s).holds, 1u);

  run.events.pop_back();  // set-points come back, the follower never follows again
  const RunVerdict stuck = run.Summarise().Verdict();
  EXPECT_FALSE(stuck.clean);
  EXPECT_EQ(stuck.reason, "watchdog_hold");
  EXPECT_NEAR(stuck.t_s, 0.53, 1e-9);
  EXPECT_EQ(stuck.holds, 0u);
  EXPECT_NE(stuck.description.find("did not follow again"), std::string::npos) << stuck.description;
}

TEST(RunVerdictTest, FaultsAndEStopsAreNotClean) {
  FollowerRun run;
  run.events = {{100, OperatingState::kEnabled}, {9000, OperatingState::kFault, FaultReason::kBackEnd}};
  const RunVerdict v = run.Summarise().Verdict();
  EXPECT_FALSE(v.clean);
  EXPECT_EQ(v.reason, "fault");
  EXPECT_NEAR(v.t_s, 0.9, 1e-9);
  run.events = {{100, OperatingState::kEnabled}, {9000, OperatingState::kEStop, FaultReason::kEStop}};
  EXPECT_EQ(run.Summarise().Verdict().reason, "estop");
}

TEST(RunVerdictTest, TheEndOfTheLeadersRunAndTheOperatorsOwnHoldsAreClean) {
  // Two processes: the leader's set-points end at 1.5 s; the follower holds 30 ms later, declares the leader lost
  // 0.5 s later, and is stopped after that.
  FollowerRun end = HeldThenLeaderLost(15300, 20000, 25000);
  end.sends_until = 15000;
  const SessionSummary summary = end.Summarise();
  const RunVerdict v = summary.Verdict();
  EXPECT_TRUE(v.clean) << v.description;
  EXPECT_EQ(v.faults, 0u);
  EXPECT_EQ(summary.Summary().at("run_clean"), true);
  EXPECT_TRUE(summary.Summary().at("run_fault").is_null());
  // The operator let go (presence off) and the follower held, while set-points kept coming.
  FollowerRun let_go;
  let_go.events = {{100, OperatingState::kEnabled}, {8001, OperatingState::kReady}};
  let_go.flags_from = 8000;
  EXPECT_TRUE(let_go.Summarise().Verdict().clean);
}

TEST(RunVerdictTest, ARunThatNeverFollowedOrDidNotEndIsNotCleanAndNoFollowerIsNotJudged) {
  FollowerRun never;
  EXPECT_EQ(never.Summarise().Verdict().reason, "never_followed");
  FollowerRun cut;
  cut.events = {{100, OperatingState::kEnabled}};
  cut.complete = false;
  EXPECT_EQ(cut.Summarise().Verdict().reason, "incomplete");
  const SessionSummary leader_only(SummaryOptions{});
  EXPECT_FALSE(leader_only.Verdict().judged);
  EXPECT_TRUE(leader_only.Summary().at("run_clean").is_null());
}

}  // namespace
}  // namespace robossis::teleop
