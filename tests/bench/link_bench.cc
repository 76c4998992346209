// Set-point latency of the DDS link, leader -> follower, at 1 kHz over loopback, with DDS Security on and off; and
// the cost of the real-time calls. Latency is the follower receive thread's clock at the take minus the leader's
// stamp before SendSetPoint (one clock in one process): it includes the wake-up of the link's send thread, the DDS
// write, the network stack and the receive thread's wake-up. Run it beside ddsperf (BENCHMARKS.md gives the
// command) to compare with Cyclone's own figures on the same machine in the same run.

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <thread>
#include <vector>

#include <benchmark/benchmark.h>

#include "src/core/rt/clock.h"
#include "src/link/dds_follower_link.h"
#include "src/link/dds_leader_link.h"
#include "src/link/keys.h"

namespace {
using namespace robossis;

std::int64_t NowNs(const rt::Clock& c) { return static_cast<std::int64_t>(std::llround(c.NowS() * 1e9)); }

// Credentials made once per run, removed at exit.
struct BenchKeys {
  std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("robossis-link-bench-keys-" + std::to_string(getpid()));
  BenchKeys() {
    std::filesystem::remove_all(dir);
    link::InitKeys(dir, {});
  }
  ~BenchKeys() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

const std::filesystem::path& Keys() {
  static const BenchKeys keys;
  return keys.dir;
}

link::LinkOptions Options(link::Role role, bool secure) {
  link::LinkOptions o;
  o.role = role;
  o.domain_id = 201 + static_cast<int>(getpid() % 20);
  o.network_interface = "127.0.0.1";
  o.peers = {"127.0.0.1"};
  o.insecure = !secure;
  if (secure) o.keys_dir = Keys() / link::ToString(role);
  return o;
}

teleop::SetPointMessage SetPoint(std::uint64_t seq, std::int64_t stamp) {
  teleop::SetPointMessage m;
  m.leader_session = 1;
  m.sequence = seq;
  m.stamp_ns = stamp;
  m.p_FM = {0, 0, 0.284};
  m.flags = teleop::kSetPointPresence;
  return m;
}

double Percentile(std::vector<double>& v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())))];
}

// Arg 0: security off/on. Each iteration is one set-point at 1 kHz.
void BM_SetPointLatency1kHz(benchmark::State& state) {
  const bool secure = state.range(0) != 0;
  rt::MonotonicClock clock;
  link::DdsFollowerLink follower(Options(link::Role::kFollower, secure), clock);
  link::DdsLeaderLink leader(Options(link::Role::kLeader, secure));
  std::uint64_t seq = 0;
  for (int i = 0; i < 20000 && follower.Statistics().setpoints_accepted < 50; ++i) {  // discovery, handshake
    leader.SendSetPoint(SetPoint(++seq, NowNs(clock)));
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  std::vector<double> latency_us;
  latency_us.reserve(100000);
  std::atomic<bool> done{false};
  std::thread consumer([&] {
    while (!done.load()) {
      teleop::SetPointMessage m;
      std::int64_t arrival = 0;
      if (follower.TakeSetPoint(m, arrival)) latency_us.push_back(1e-3 * static_cast<double>(arrival - m.stamp_ns));
      std::this_thread::sleep_for(std::chrono::microseconds(50));
    }
  });
  auto next = std::chrono::steady_clock::now();
  for (auto _ : state) {
    next += std::chrono::milliseconds(1);
    std::this_thread::sleep_until(next);
    leader.SendSetPoint(SetPoint(++seq, NowNs(clock)));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  done.store(true);
  consumer.join();
  state.counters["samples"] = static_cast<double>(latency_us.size());
  state.counters["p50_us"] = Percentile(latency_us, 0.50);
  state.counters["p99_us"] = Percentile(latency_us, 0.99);
  state.counters["max_us"] = latency_us.empty() ? 0 : latency_us.back();
  state.counters["p99_share_of_1ms_tick"] = Percentile(latency_us, 0.99) / 1000.0;
}
BENCHMARK(BM_SetPointLatency1kHz)->ArgName("secure")->Arg(0)->Arg(1)->Iterations(10000)->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// The leader's real-time call: seqlock publish + eventfd write.
void BM_SendSetPointCall(benchmark::State& state) {
  link::DdsLeaderLink leader(Options(link::Role::kLeader, false));
  rt::MonotonicClock clock;
  std::uint64_t seq = 0;
  for (auto _ : state) leader.SendSetPoint(SetPoint(++seq, NowNs(clock)));
}
BENCHMARK(BM_SendSetPointCall);

}  // namespace
