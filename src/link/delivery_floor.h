#pragma once
// The age judgement that set-points and state commands share. The two units' clocks are not synchronised, so the
// age of a message cannot be read off its stamp: a session's fastest delivery (the smallest arrival − stamp: clock
// offset + minimum latency) is the reference, and a message arriving more than max_age later than that is stale.
// The reference may creep up by the drift allowance with the elapsed time, so a receiver clock running fast is
// absorbed. A delay present from the session's first message is not seen. Plain logic: no allocation, no locks, and
// no signed overflow for any int64 stamp or arrival (the differences saturate).

#include <cstdint>

namespace robossis::link {

// a - b without signed overflow (a stamp from the wire may be any int64): clamped to the int64 range.
std::int64_t SaturatingSub(std::int64_t a, std::int64_t b) noexcept;

class DeliveryFloor {
 public:
  // The first message of a session: its delivery is the reference.
  void Start(std::int64_t stamp_ns, std::int64_t arrival_ns) noexcept;
  // A later message of the session: false if it arrived more than max_age_ns after the fastest delivery (stale);
  // otherwise it is taken (the reference and the last arrival advance) and the result is true.
  bool Admit(std::int64_t stamp_ns, std::int64_t arrival_ns, std::int64_t max_age_ns, double drift_allowance) noexcept;
  std::int64_t last_arrival_ns() const noexcept { return last_arrival_ns_; }

 private:
  std::int64_t last_arrival_ns_ = 0;
  double min_offset_ns_ = 0;  // smallest arrival − stamp of the session, allowed to creep up by the drift
};

}  // namespace robossis::link
