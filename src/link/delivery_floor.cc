#include "src/link/delivery_floor.h"

#include <algorithm>
#include <limits>

namespace robossis::link {

std::int64_t SaturatingSub(std::int64_t a, std::int64_t b) noexcept {
  std::int64_t d = 0;
  if (!__builtin_sub_overflow(a, b, &d)) return d;
  return b < 0 ? std::numeric_limits<std::int64_t>::max() : std::numeric_limits<std::int64_t>::min();
}

void DeliveryFloor::Start(std::int64_t stamp_ns, std::int64_t arrival_ns) noexcept {
  last_arrival_ns_ = arrival_ns;
  min_offset_ns_ = static_cast<double>(SaturatingSub(arrival_ns, stamp_ns));
}

bool DeliveryFloor::Admit(std::int64_t stamp_ns, std::int64_t arrival_ns, std::int64_t max_age_ns,
                          double drift_allowance) noexcept {
  // The session's fastest delivery, allowed to creep up with the elapsed time (clock drift).
  const double elapsed = static_cast<double>(std::max<std::int64_t>(0, SaturatingSub(arrival_ns, last_arrival_ns_)));
  const double offset = static_cast<double>(SaturatingSub(arrival_ns, stamp_ns));
  const double floor = std::min(min_offset_ns_ + drift_allowance * elapsed, offset);
  if (offset - floor > static_cast<double>(max_age_ns)) return false;
  min_offset_ns_ = floor;
  last_arrival_ns_ = arrival_ns;
  return true;
}

}  // namespace robossis::link
