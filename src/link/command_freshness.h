#pragma once
// Application-level freshness of state commands, on top of DDS Security (which authenticates the sender and its
// right to publish commands, but does not stop an authenticated sample from being captured and sent again). A
// command that is not newer than the last accepted one of its sender's session (same or lower sequence, same or
// older stamp) is dropped as replayed; one that arrives more than max_age after the session's fastest delivery is
// dropped as stale (the clocks are not synchronised: as for set-points, age is judged against the session's fastest
// delivery, delivery_floor.h). The caller counts the drops.
//
// Several senders may command (the panel, a restarted panel): the last kCommandSessions sessions are remembered.
// A command from a session never seen is the start of a new session and is accepted; a session forgotten since
// (more than kCommandSessions newer ones) is not recognised. Plain logic: no allocation, no locks.

#include <array>
#include <cstddef>
#include <cstdint>

#include "src/link/delivery_floor.h"
#include "src/teleop/link_messages.h"

namespace robossis::link {

// Sender sessions remembered [assumed]: a panel restarted 16 times in one follower run is far beyond normal use.
inline constexpr std::size_t kCommandSessions = 16;

enum class CommandFreshness : std::uint8_t {
  kAccepted,
  kReplayed,  // sequence or stamp not above the last accepted command of its session
  kStale,     // arrived later than max_age after the session's fastest delivery
};
const char* ToString(CommandFreshness f);

class CommandFilter {
 public:
  CommandFilter(std::int64_t max_age_ns, double drift_allowance) noexcept
      : max_age_ns_(max_age_ns), drift_allowance_(drift_allowance) {}

  // Judges one command arriving at `arrival_ns` (the follower's clock) and, if accepted, advances its session.
  CommandFreshness Check(const teleop::StateCommandMessage& m, std::int64_t arrival_ns) noexcept;

 private:
  struct Session {
    bool used = false;
    std::uint64_t session = 0;
    std::uint64_t last_sequence = 0;
    std::int64_t last_stamp_ns = 0;
    DeliveryFloor delivery;
  };
  std::int64_t max_age_ns_;
  double drift_allowance_;
  std::array<Session, kCommandSessions> sessions_{};
  std::size_t next_ = 0;  // the slot a new session takes (the oldest remembered)
};

}  // namespace robossis::link
