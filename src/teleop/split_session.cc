#include "src/teleop/split_session.h"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "src/teleop/flight_recorder.h"
#include "src/teleop/session_log.h"
#include "src/teleop/session_summary.h"

namespace robossis::teleop {

namespace {

SessionLog ReadUnitLog(const std::filesystem::path& file, const char* unit) {
  SessionLog log = ReadSessionLog(file);
  const std::string units = log.meta.value("units", "both");
  if (units != unit) {
    throw std::runtime_error(file.string() + ": a log of the " + units + " units, expected the " + unit +
                             "'s own (robossis " + unit + ")");
  }
  return log;
}

// Each loop's figures from the process that ran it; the session's time is the longer of the two runs (the follower
// starts first and stops last).
SessionEndRecord JoinEnds(const SessionEndRecord& leader, const SessionEndRecord& follower) {
  SessionEndRecord end = follower;
  end.elapsed_s = std::max(leader.elapsed_s, follower.elapsed_s);
  end.leader_loop_ticks = leader.leader_loop_ticks;
  end.leader_overruns = leader.leader_overruns;
  end.leader_overruns_late_wake = leader.leader_overruns_late_wake;
  end.leader_overruns_long_tick = leader.leader_overruns_long_tick;
  end.leader_period_jitter_us_p99 = leader.leader_period_jitter_us_p99;
  end.leader_period_jitter_us_max = leader.leader_period_jitter_us_max;
  end.leader_wake_latency_us_p99 = leader.leader_wake_latency_us_p99;
  end.leader_records_dropped = leader.leader_records_dropped;
  end.device_failures = leader.device_failures;
  end.ik_rejected = leader.ik_rejected;
  return end;
}

}  // namespace

TeleopOutputs ReplaySplitSession(const std::filesystem::path& leader_log, const std::filesystem::path& follower_log) {
  const SessionLog leader = ReadUnitLog(leader_log, "leader");
  const SessionLog follower = ReadUnitLog(follower_log, "follower");
  SummaryOptions options;
  try {
    options = SummaryOptionsFromMeta(leader.meta);  // the leader's rate, caps and feedback map
    options.follower_rate_hz = follower.meta.at("follower_rate_hz").get<double>();
  } catch (const std::exception& e) {
    throw std::runtime_error(leader_log.string() + ", " + follower_log.string() +
                             ": the headers' meta lacks the loop rates: " + e.what());
  }
  // Without the follower link's offset the stamps cannot be put on the follower's clock: not judged.
  const bool joinable = follower.meta.contains("status_stamp_offset_ns");
  if (!joinable) options.feedback_map_known = false;
  const std::int64_t offset_ns = joinable ? follower.meta.at("status_stamp_offset_ns").get<std::int64_t>() : 0;

  SessionSummary summary(options);
  std::vector<SessionEndRecord> leader_end, follower_end;
  std::string where = leader_log.string() + ": ";
  try {
    for (LeaderTickRecord r : leader.Decode<LeaderTickRecord>("leader", LeaderStreamSpec())) {
      r.follower_stamp_ns -= offset_ns;
      summary.AddLeader(r);
    }
    leader_end = leader.Decode<SessionEndRecord>("end", EndStreamSpec());
    where = follower_log.string() + ": ";
    for (const auto& r : follower.Decode<FollowerTickRecord>("follower", FollowerStreamSpec())) summary.AddFollower(r);
    follower_end = follower.Decode<SessionEndRecord>("end", EndStreamSpec());
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(where + e.what());
  }
  if (!leader_end.empty() && !follower_end.empty()) summary.SetEnd(JoinEnds(leader_end.back(), follower_end.back()));

  TeleopOutputs out;
  out.summary = summary.Summary();
  out.leader_csv = summary.leader_csv();
  out.follower_csv = summary.follower_csv();
  out.periods_csv = summary.PeriodsCsv();
  out.summary["units"] = "both";
  if (leader.truncated) out.warnings.push_back(leader_log.string() + ": the last frame was cut short (the run was killed)");
  if (follower.truncated) {
    out.warnings.push_back(follower_log.string() + ": the last frame was cut short (the run was killed)");
  }
  return out;
}

}  // namespace robossis::teleop
