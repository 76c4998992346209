#include "src/link/setpoint_freshness.h"

#include <algorithm>

namespace robossis::link {

const char* ToString(Freshness f) {
  switch (f) {
    case Freshness::kAccepted: return "accepted";
    case Freshness::kStale: return "stale";
    case Freshness::kReplayed: return "replayed";
    case Freshness::kRetiredSession: return "retired_session";
    case Freshness::kConcurrentSession: return "concurrent_session";
  }
  return "?";
}

bool SetPointFreshness::IsRetired(std::uint64_t session) const noexcept {
  for (std::size_t i = 0; i < retired_count_; ++i) {
    if (retired_[i] == session) return true;
  }
  return false;
}

void SetPointFreshness::StartSession(const teleop::SetPointMessage& m, std::int64_t arrival_ns) noexcept {
  if (have_session_) {
    retired_[retired_next_] = session_;
    retired_next_ = (retired_next_ + 1) % retired_.size();
    retired_count_ = std::min(retired_count_ + 1, retired_.size());
  }
  have_session_ = true;
  session_ = m.leader_session;
  last_sequence_ = m.sequence;
  delivery_.Start(m.stamp_ns, arrival_ns);
}

Freshness SetPointFreshness::Check(const teleop::SetPointMessage& m, std::int64_t arrival_ns) noexcept {
  if (!have_session_ || m.leader_session != session_) {
    if (IsRetired(m.leader_session)) return Freshness::kRetiredSession;
    if (have_session_ && SaturatingSub(arrival_ns, delivery_.last_arrival_ns()) < takeover_ns_) {
      return Freshness::kConcurrentSession;
    }
    StartSession(m, arrival_ns);
    return Freshness::kAccepted;
  }
  if (m.sequence <= last_sequence_) return Freshness::kReplayed;
  if (!delivery_.Admit(m.stamp_ns, arrival_ns, max_age_ns_, drift_allowance_)) return Freshness::kStale;
  last_sequence_ = m.sequence;
  return Freshness::kAccepted;
}

}  // namespace robossis::link
