// libFuzzer target: the follower link's freshness filter (src/link/setpoint_freshness.h). The input is the filter's
// parameters, then a sequence of set-points as an authenticated but broken or hostile leader could send them, each
// with an arrival time: any int64 stamp, sequence, session or arrival (INT64_MIN and INT64_MAX included). Every
// set-point gets a verdict without undefined behaviour (the fuzz build's UBSan aborts on a signed overflow), and an
// accepted one is of the current session and, within it, newer than the last accepted.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "src/link/setpoint_freshness.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using robossis::link::Freshness;
  // The parameters: max age and takeover (ns), drift allowance.
  constexpr std::size_t kHeader = 2 * sizeof(std::int64_t) + sizeof(double);
  if (size < kHeader) return 0;
  std::int64_t max_age_ns = 0, takeover_ns = 0;
  double drift = 0;
  std::memcpy(&max_age_ns, data, sizeof max_age_ns);
  std::memcpy(&takeover_ns, data + sizeof max_age_ns, sizeof takeover_ns);
  std::memcpy(&drift, data + 2 * sizeof(std::int64_t), sizeof drift);
  robossis::link::SetPointFreshness filter(max_age_ns, takeover_ns, drift);
  // One record: the message's bytes, then the arrival (ns of the follower's clock).
  constexpr std::size_t kRecord = sizeof(robossis::teleop::SetPointMessage) + sizeof(std::int64_t);
  bool have_accepted = false;
  std::uint64_t last_session = 0, last_sequence = 0;
  for (std::size_t off = kHeader; off + kRecord <= size; off += kRecord) {
    robossis::teleop::SetPointMessage m;
    std::memcpy(static_cast<void*>(&m), data + off, sizeof m);
    std::int64_t arrival_ns = 0;
    std::memcpy(&arrival_ns, data + off + sizeof m, sizeof arrival_ns);
    if (filter.Check(m, arrival_ns) != Freshness::kAccepted) continue;
    if (filter.current_session() != m.leader_session) std::abort();  // accepted from another session
    if (have_accepted && m.leader_session == last_session && m.sequence <= last_sequence) std::abort();  // a replay
    have_accepted = true;
    last_session = m.leader_session;
    last_sequence = m.sequence;
  }
  return 0;
}
