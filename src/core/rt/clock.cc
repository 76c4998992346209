#include "src/core/rt/clock.h"

#include <time.h>

namespace robossis::rt {

std::int64_t MonotonicNowNs() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

MonotonicClock::MonotonicClock() noexcept : epoch_ns_(MonotonicNowNs()) {}

double MonotonicClock::NowS() const noexcept { return 1e-9 * static_cast<double>(MonotonicNowNs() - epoch_ns_); }

}  // namespace robossis::rt
