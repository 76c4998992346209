#pragma once
// Shared by the DDS link tests: credentials made once per test process, a domain per process (so tests running in
// parallel never hear each other), and polling helpers with generous timeouts (no timing assertions).

#include <chrono>
#include <filesystem>
#include <functional>
#include <string>

#include "src/link/link_options.h"
#include "src/teleop/link_messages.h"

namespace robossis::link::testing {

// A DDS domain unique to this process (1..200).
int TestDomain();
// Credentials made by InitKeys in a temporary folder, once per process (removed at exit): a folder per role.
const std::filesystem::path& TestKeys();
// Loopback options for `role`, secured with TestKeys() unless `insecure`.
LinkOptions LoopbackOptions(Role role, bool insecure = false);
// Polls `done` every millisecond until it is true or `timeout` passes; returns its last value.
bool WaitFor(const std::function<bool()>& done, std::chrono::milliseconds timeout = std::chrono::seconds(10));
// A sane set-point near the RSR's home pose.
teleop::SetPointMessage MakeSetPoint(std::uint64_t session, std::uint64_t sequence, std::int64_t stamp_ns);

}  // namespace robossis::link::testing
