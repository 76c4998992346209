#pragma once
// What a link end counts (read from any thread; the link threads write them).

#include <atomic>
#include <cstdint>

#include <nlohmann/json_fwd.hpp>

namespace robossis::link {

struct FollowerLinkStatistics {
  std::uint64_t setpoints_received = 0;     // samples taken from DDS
  std::uint64_t setpoints_accepted = 0;     // handed to the follower unit
  std::uint64_t dropped_stale = 0;          // older than max_age_s (freshness)
  std::uint64_t dropped_replayed = 0;       // duplicate, replayed or out of order (freshness)
  std::uint64_t dropped_session = 0;        // retired or concurrent leader session (freshness)
  std::uint64_t rejected_invalid = 0;       // not finite or beyond the sanity bounds (validation)
  std::uint64_t commands_received = 0;
  std::uint64_t commands_dropped = 0;       // unknown command string or the command queue full
  std::uint64_t commands_replayed = 0;      // not newer than the last of its session (command_freshness)
  std::uint64_t commands_stale = 0;         // older than command max_age_s (command_freshness)
  std::uint64_t estops_received = 0;        // E-stops engaged (estop samples and "estop" commands)
  std::uint64_t status_published = 0;
  std::uint64_t deadline_missed = 0;        // DDS requested-deadline-missed events on the set-point reader
  std::uint32_t leaders_alive = 0;          // DDS liveliness: set-point writers alive now
};

struct LeaderLinkStatistics {
  std::uint64_t setpoints_sent = 0;
  std::uint64_t commands_sent = 0;
  std::uint64_t commands_refused = 0;       // the command queue was full, or no command writer (a leader)
  std::uint64_t estops_sent = 0;            // E-stop samples written (several engaged at once are one)
  std::uint64_t status_received = 0;        // measured_cp samples
  std::uint64_t state_received = 0;         // operating_state samples
  std::uint32_t followers_matched = 0;      // set-point readers matched now
};

// The counters as the units' summary.json reports them (key "link").
nlohmann::ordered_json ToJson(const FollowerLinkStatistics& s);
nlohmann::ordered_json ToJson(const LeaderLinkStatistics& s);

}  // namespace robossis::link
