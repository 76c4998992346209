#include "src/teleop/run_verdict.h"

#include <cstdio>
#include <stdexcept>
#include <utility>

namespace robossis::teleop {

namespace {

std::string Seconds(double t_s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f s", t_s);
  return buf;
}

// The leader asks the follower to follow: presence, no clutch, no device failure.
bool LeaderAsksToFollow(std::uint8_t flags) {
  return (flags & kSetPointPresence) != 0 && (flags & (kSetPointClutched | kSetPointDeviceFault)) == 0;
}

}  // namespace

void RunVerdictCheck::Fault(double t_s, std::string reason, std::string description) {
  if (faults_++ > 0) return;
  first_.t_s = t_s;
  first_.reason = std::move(reason);
  first_.description = std::move(description);
}

// The episode ends: following resumed at end_s (resumed) or the run went on without it. Counted once confirmed.
void RunVerdictCheck::CloseEpisode(double end_s, bool resumed) {
  if (resumed && reason_ == "watchdog_hold") {
    ++holds_;
    hold_s_ += end_s - start_s_;
  } else if (resumed || confirmed_) {  // resumed: the leader was sending
    Fault(start_s_, reason_,
          "stopped following at " + Seconds(start_s_) + " while the leader still sent set-points: " + what_ +
              (resumed ? "; followed again at " + Seconds(end_s) : "; did not follow again"));
  }
  open_ = false;
  confirmed_ = false;
}

void RunVerdictCheck::AddFollower(const FollowerTickRecord& r) {
  const double t = r.time_s;
  seen_ = true;
  last_t_s_ = t;
  const OperatingState before = state_;
  state_ = r.state;
  if (r.state == OperatingState::kFault || r.state == OperatingState::kEStop) {
    if (before == r.state) return;
    if (open_) CloseEpisode(t, false);
    std::string what = r.state == OperatingState::kEStop ? "E-stop" : std::string("fault: ") + ToString(r.reason);
    if (r.reason == FaultReason::kBackEnd) {
      what += std::string(" (") + robot::ToString(static_cast<robot::FollowerFault>(r.back_end_fault)) + ")";
    }
    Fault(t, r.state == OperatingState::kEStop ? "estop" : "fault", what + " at " + Seconds(t));
    return;
  }
  if (r.state == OperatingState::kEnabled) {
    followed_ = true;
    if (open_) CloseEpisode(t, true);
    return;
  }
  const bool disabled = r.state == OperatingState::kDisabled;
  const bool asked = before == OperatingState::kEnabled && LeaderAsksToFollow(r.setpoint_flags);
  if (disabled && (asked || (open_ && before != OperatingState::kDisabled))) {
    const bool lost = r.reason == FaultReason::kLeaderLost;
    const std::string what =
        (lost ? "the leader declared lost and the drives disabled at " : "disabled at ") + Seconds(t);
    if (asked) {
      what_ = what;
    } else {
      what_ += ", then " + what;  // a hold that went on until the leader was declared lost
    }
    reason_ = lost ? "leader_lost" : "disabled";
  } else if (asked) {
    what_ = "held by the watchdog (no valid set-point for its hold time)";
    reason_ = "watchdog_hold";
  }
  if (asked) {
    open_ = true;
    confirmed_ = false;
    start_s_ = t;
  }
  if (open_ && r.took_setpoint && t > start_s_) confirmed_ = true;
}

RunVerdict RunVerdictCheck::Verdict(bool complete) const {
  RunVerdictCheck end = *this;  // an episode still open at the end counts if set-points arrived after its start
  if (end.open_) end.CloseEpisode(last_t_s_, false);
  RunVerdict v = end.first_;
  v.judged = seen_;
  v.faults = end.faults_;
  v.holds = end.holds_;
  v.hold_s = end.hold_s_;
  if (!seen_) return v;
  auto add = [&v](const char* reason, const char* description) {
    if (v.faults++ > 0) return;
    v.reason = reason;
    v.description = description;
  };
  if (!followed_) add("never_followed", "the follower never followed (never enabled)");
  if (!complete) add("incomplete", "the run did not end (its log has no end record)");
  v.clean = v.faults == 0;
  return v;
}

void WriteRunVerdict(const RunVerdict& v, nlohmann::ordered_json& summary) {
  summary["run_clean"] = v.judged ? nlohmann::ordered_json(v.clean) : nlohmann::ordered_json();
  summary["run_faults"] = v.faults;
  summary["run_fault"] =
      v.judged && !v.clean
          ? nlohmann::ordered_json{{"t_s", v.t_s}, {"reason", v.reason}, {"description", v.description}}
          : nlohmann::ordered_json();
  summary["run_holds"] = v.holds;
  summary["run_hold_s"] = v.hold_s;
}

RunVerdict ReadRunVerdict(const nlohmann::ordered_json& summary) {
  for (const char* key : {"run_clean", "run_faults", "run_fault", "run_holds", "run_hold_s"}) {
    if (!summary.contains(key)) {
      throw std::invalid_argument(std::string("summary.json: no '") + key +
                                  "'; expected the run's verdict (a summary written by this version)");
    }
  }
  RunVerdict v;
  v.judged = !summary["run_clean"].is_null();
  v.clean = v.judged && summary["run_clean"].get<bool>();
  v.faults = summary["run_faults"].get<std::uint64_t>();
  v.holds = summary["run_holds"].get<std::uint64_t>();
  v.hold_s = summary["run_hold_s"].get<double>();
  if (const auto& f = summary["run_fault"]; f.is_object()) {
    v.t_s = f.at("t_s").get<double>();
    v.reason = f.at("reason").get<std::string>();
    v.description = f.at("description").get<std::string>();
  }
  return v;
}

}  // namespace robossis::teleop
