#include "src/link/command_freshness.h"

#include <algorithm>

namespace robossis::link {

const char* ToString(CommandFreshness f) {
  switch (f) {
    case CommandFreshness::kAccepted: return "accepted";
    case CommandFreshness::kReplayed: return "replayed";
    case CommandFreshness::kStale: return "stale";
  }
  return "?";
}

CommandFreshness CommandFilter::Check(const teleop::StateCommandMessage& m, std::int64_t arrival_ns) noexcept {
  Session* s = std::find_if(sessions_.begin(), sessions_.end(),
                            [&](const Session& x) { return x.used && x.session == m.session; });
  if (s == sessions_.end()) {  // a new sender session: its first command sets the reference
    s = &sessions_[next_];
    next_ = (next_ + 1) % sessions_.size();
    *s = Session{true, m.session, m.sequence, m.stamp_ns, {}};
    s->delivery.Start(m.stamp_ns, arrival_ns);
    return CommandFreshness::kAccepted;
  }
  if (m.sequence <= s->last_sequence || m.stamp_ns <= s->last_stamp_ns) return CommandFreshness::kReplayed;
  if (!s->delivery.Admit(m.stamp_ns, arrival_ns, max_age_ns_, drift_allowance_)) return CommandFreshness::kStale;
  s->last_sequence = m.sequence;
  s->last_stamp_ns = m.stamp_ns;
  return CommandFreshness::kAccepted;
}

}  // namespace robossis::link
