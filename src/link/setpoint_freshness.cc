#include "src/link/setpoint_freshness.h"

#include <algorithm>
#include <limits>

namespace robossis::link {

namespace {
// a - b without signed overflow (a stamp from the wire may be any int64): clamped to the int64 range.
std::int64_t SaturatingSub(std::int64_t a, std::int64_t b) noexcept {
  std::int64_t d = 0;
  if (!__builtin_sub_overflow(a, b, &d)) return d;
  return b < 0 ? std::numeric_limits<std::int64_t>::max() : std::numeric_limits<std::int64_t>::min();
}
}  // namespace

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
  last_arrival_ns_ = arrival_ns;
  min_offset_ns_ = static_cast<double>(SaturatingSub(arrival_ns, m.stamp_ns));
}

Freshness SetPointFreshness::Check(const teleop::SetPointMessage& m, std::int64_t arrival_ns) noexcept {
  if (!have_session_ || m.leader_session != session_) {
    if (IsRetired(m.leader_session)) return Freshness::kRetiredSession;
    if (have_session_ && SaturatingSub(arrival_ns, last_arrival_ns_) < takeover_ns_) return Freshness::kConcurrentSession;
    StartSession(m, arrival_ns);
    return Freshness::kAccepted;
  }
  if (m.sequence <= last_sequence_) return Freshness::kReplayed;
  // The session's fastest delivery, allowed to creep up with the elapsed time (clock drift).
  const double elapsed =
      static_cast<double>(std::max<std::int64_t>(0, SaturatingSub(arrival_ns, last_arrival_ns_)));
  const double offset = static_cast<double>(SaturatingSub(arrival_ns, m.stamp_ns));
  const double floor = std::min(min_offset_ns_ + drift_allowance_ * elapsed, offset);
  if (offset - floor > static_cast<double>(max_age_ns_)) return Freshness::kStale;
  min_offset_ns_ = floor;
  last_sequence_ = m.sequence;
  last_arrival_ns_ = arrival_ns;
  return Freshness::kAccepted;
}

}  // namespace robossis::link
