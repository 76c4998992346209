#include "tests/link/link_test_support.h"

#include <unistd.h>

#include <cstdlib>
#include <thread>

#include "src/link/keys.h"

namespace robossis::link::testing {

int TestDomain() { return 1 + static_cast<int>(getpid() % 200); }

namespace {
struct KeysFolder {
  std::filesystem::path dir;
  KeysFolder() {
    dir = std::filesystem::temp_directory_path() / ("robossis-link-test-keys-" + std::to_string(getpid()));
    std::filesystem::remove_all(dir);
    InitKeys(dir, KeysInitOptions{});
  }
  ~KeysFolder() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};
}  // namespace

const std::filesystem::path& TestKeys() {
  static KeysFolder keys;
  return keys.dir;
}

LinkOptions LoopbackOptions(Role role, bool insecure) {
  LinkOptions o;
  o.role = role;
  o.domain_id = TestDomain();
  o.network_interface = "127.0.0.1";
  o.peers = {"127.0.0.1"};
  o.insecure = insecure;
  if (!insecure) o.keys_dir = TestKeys() / ToString(role);
  return o;
}

bool WaitFor(const std::function<bool()>& done, std::chrono::milliseconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return done();
}

teleop::SetPointMessage MakeSetPoint(std::uint64_t session, std::uint64_t sequence, std::int64_t stamp_ns) {
  teleop::SetPointMessage m;
  m.leader_session = session;
  m.sequence = sequence;
  m.stamp_ns = stamp_ns;
  m.p_FM = {0.001 * static_cast<double>(sequence % 10), 0.0, 0.284};
  m.q_FM = {1, 0, 0, 0};
  m.twist_F = {0.01, 0, 0, 0, 0, 0.1};
  m.flags = teleop::kSetPointPresence;
  return m;
}

}  // namespace robossis::link::testing
