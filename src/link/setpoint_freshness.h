#pragma once
// Application-level freshness of set-points, on top of DDS Security: a set-point that is out of order, replayed,
// from a retired leader session, or older than the age limit is dropped (and counted by the caller).
//
// Age is judged against the session's fastest delivery (delivery_floor.h: the clocks are not synchronised); a delay
// present from the session's very first set-point is not seen (the follower's watchdog still holds on silence).
// Plain logic: no allocation, no locks, and no signed overflow for any int64 stamp or arrival.

#include <array>
#include <cstdint>

#include "src/link/delivery_floor.h"
#include "src/teleop/link_messages.h"

namespace robossis::link {

enum class Freshness : std::uint8_t {
  kAccepted,
  kStale,            // arrived later than max_age after the session's fastest delivery
  kReplayed,         // sequence not above the last accepted one (duplicate, replay or reordering)
  kRetiredSession,   // from a leader session this follower has already left
  kConcurrentSession // another leader session while the current one is still sending
};
const char* ToString(Freshness f);

class SetPointFreshness {
 public:
  SetPointFreshness(std::int64_t max_age_ns, std::int64_t takeover_ns, double drift_allowance) noexcept
      : max_age_ns_(max_age_ns), takeover_ns_(takeover_ns), drift_allowance_(drift_allowance) {}

  // Judges one set-point arriving at `arrival_ns` (the follower's clock) and, if accepted, advances the state.
  Freshness Check(const teleop::SetPointMessage& m, std::int64_t arrival_ns) noexcept;

  std::uint64_t current_session() const noexcept { return session_; }

 private:
  bool IsRetired(std::uint64_t session) const noexcept;
  void StartSession(const teleop::SetPointMessage& m, std::int64_t arrival_ns) noexcept;

  std::int64_t max_age_ns_;
  std::int64_t takeover_ns_;
  double drift_allowance_;
  bool have_session_ = false;
  std::uint64_t session_ = 0;
  std::uint64_t last_sequence_ = 0;
  DeliveryFloor delivery_;
  std::array<std::uint64_t, 16> retired_{};
  std::size_t retired_next_ = 0;
  std::size_t retired_count_ = 0;
};

}  // namespace robossis::link
