// Fault injection between a secured leader and follower: each lives in a network namespace of its own, and all their
// traffic crosses a UDP relay (src/link/fault_relay.h) in a third namespace, which drops, duplicates, reorders,
// stalls and replays packets. The namespaces are made by the test and removed by it (root only; skipped otherwise).
//
// Every case checks what must hold whatever the network does: no set-point reaches the follower out of order or
// older than the age limit, and no replayed set-point is accepted. The figures of each case (delivery, drops by
// reason, the longest silence the follower saw) are printed as a table row (RELIABILITY.md).

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <memory>
#include <thread>

#include <gtest/gtest.h>

#include "src/core/rt/clock.h"
#include "src/link/dds_follower_link.h"
#include "src/link/dds_leader_link.h"
#include "src/link/fault_relay.h"
#include "tests/link/link_test_support.h"
#include "tests/link/net_namespace.h"

namespace robossis::link {
namespace {

using testing::NetNamespace;
using testing::Shell;

constexpr int kDomain = 7;  // private namespaces: no other test can hear it
constexpr std::uint16_t kPortBase = 7400 + 250 * kDomain;
constexpr std::uint16_t kFollowerDisc = kPortBase + 10, kFollowerData = kPortBase + 11;  // participant index 0
constexpr std::uint16_t kLeaderDisc = kPortBase + 12, kLeaderData = kPortBase + 13;      // participant index 1
constexpr std::int64_t kMaxAgeNs = 30000000;

std::int64_t NowNs(const rt::Clock& c) { return static_cast<std::int64_t>(std::llround(c.NowS() * 1e9)); }

// leader (ns L, 10.99.2.2) ⇄ relay (ns R, 10.99.2.1 | 10.99.1.1) ⇄ follower (ns F, 10.99.1.2)
class RelayedPair {
 public:
  RelayedPair()
      : tag_(std::to_string(getpid())),
        relay_ns_("rbs-relay-" + tag_),
        follower_ns_("rbs-follower-" + tag_),
        leader_ns_("rbs-leader-" + tag_) {
    const std::string r = "ip -n " + relay_ns_.name() + " ";
    Shell(r + "link add rf type veth peer name f0 netns " + follower_ns_.name());
    Shell(r + "link add rl type veth peer name l0 netns " + leader_ns_.name());
    Shell(r + "addr add 10.99.1.1/24 dev rf && " + r + "link set rf up");
    Shell(r + "addr add 10.99.2.1/24 dev rl && " + r + "link set rl up");
    Shell("ip -n " + follower_ns_.name() + " addr add 10.99.1.2/24 dev f0 && ip -n " + follower_ns_.name() +
          " link set f0 up");
    Shell("ip -n " + leader_ns_.name() + " addr add 10.99.2.2/24 dev l0 && ip -n " + leader_ns_.name() +
          " link set l0 up");
    relay_ns_.Run([&] {
      relay_ = std::make_unique<FaultRelay>(
          std::vector<RelayRoute>{{"10.99.2.1", kFollowerDisc, "10.99.1.2", kFollowerDisc},
                                  {"10.99.2.1", kFollowerData, "10.99.1.2", kFollowerData},
                                  {"10.99.1.1", kLeaderDisc, "10.99.2.2", kLeaderDisc},
                                  {"10.99.1.1", kLeaderData, "10.99.2.2", kLeaderData}},
          /*seed=*/20261201);
    });
    LinkOptions f = testing::LoopbackOptions(Role::kFollower);
    f.domain_id = kDomain;
    f.network_interface = "10.99.1.2";
    f.external_address = "10.99.2.1";  // the leader reaches the follower through the relay
    f.participant_index = 0;
    f.peers = {"10.99.1.1:" + std::to_string(kLeaderDisc)};
    LinkOptions l = testing::LoopbackOptions(Role::kLeader);
    l.domain_id = kDomain;
    l.network_interface = "10.99.2.2";
    l.external_address = "10.99.1.1";
    l.participant_index = 1;
    l.peers = {"10.99.2.1:" + std::to_string(kFollowerDisc)};
    follower_ns_.Run([&] { follower_ = std::make_unique<DdsFollowerLink>(f, clock_); });
    leader_ns_.Run([&] { leader_ = std::make_unique<DdsLeaderLink>(l); });
  }
  ~RelayedPair() {
    leader_.reset();
    follower_.reset();
    relay_.reset();
  }

  rt::MonotonicClock clock_;
  std::string tag_;
  NetNamespace relay_ns_, follower_ns_, leader_ns_;
  std::unique_ptr<FaultRelay> relay_;
  std::unique_ptr<DdsFollowerLink> follower_;
  std::unique_ptr<DdsLeaderLink> leader_;
};

struct CaseFigures {
  std::uint64_t sent = 0, written = 0, taken = 0, taken_out_of_order = 0, taken_too_old = 0;
  double max_age_ms = 0, max_gap_ms = 0;
  std::uint64_t gaps_over_30ms = 0;
  FollowerLinkStatistics link;
  RelayStatistics relay;
};

// Streams set-points at 1 kHz for `duration_s` while a follower-side thread takes them at 1 kHz, as the follower
// tick does, and checks every one it takes.
CaseFigures Stream(RelayedPair& pair, std::uint64_t session, std::uint64_t& seq, double duration_s) {
  CaseFigures fig;
  const FollowerLinkStatistics link0 = pair.follower_->Statistics();
  const RelayStatistics relay0 = pair.relay_->Statistics();
  const std::uint64_t written0 = pair.leader_->Statistics().setpoints_sent;
  std::atomic<bool> done{false};
  std::thread consumer([&] {
    std::uint64_t last_seq = 0;
    std::int64_t last_arrival = 0;
    auto next = std::chrono::steady_clock::now();
    while (!done.load()) {
      next += std::chrono::milliseconds(1);
      std::this_thread::sleep_until(next);
      teleop::SetPointMessage m;
      std::int64_t arrival = 0;
      if (!pair.follower_->TakeSetPoint(m, arrival)) continue;
      ++fig.taken;
      if (m.sequence <= last_seq) ++fig.taken_out_of_order;
      const std::int64_t age = arrival - m.stamp_ns;  // one clock for both ends in this test
      if (age > kMaxAgeNs + 2000000) ++fig.taken_too_old;  // 2 ms: the fastest delivery the filter measures from
      fig.max_age_ms = std::max(fig.max_age_ms, 1e-6 * static_cast<double>(age));
      if (last_arrival != 0) {
        const double gap_ms = 1e-6 * static_cast<double>(arrival - last_arrival);
        fig.max_gap_ms = std::max(fig.max_gap_ms, gap_ms);
        if (gap_ms > 30.0) ++fig.gaps_over_30ms;
      }
      last_seq = m.sequence;
      last_arrival = arrival;
    }
  });
  auto next = std::chrono::steady_clock::now();
  const auto end = next + std::chrono::microseconds(static_cast<long long>(duration_s * 1e6));
  while (next < end) {
    next += std::chrono::milliseconds(1);
    std::this_thread::sleep_until(next);
    pair.leader_->SendSetPoint(testing::MakeSetPoint(session, ++seq, NowNs(pair.clock_)));
    ++fig.sent;
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // let stalled packets drain
  done.store(true);
  consumer.join();
  fig.written = pair.leader_->Statistics().setpoints_sent - written0;
  const FollowerLinkStatistics l = pair.follower_->Statistics();
  fig.link.setpoints_received = l.setpoints_received - link0.setpoints_received;
  fig.link.setpoints_accepted = l.setpoints_accepted - link0.setpoints_accepted;
  fig.link.dropped_stale = l.dropped_stale - link0.dropped_stale;
  fig.link.dropped_replayed = l.dropped_replayed - link0.dropped_replayed;
  fig.link.dropped_session = l.dropped_session - link0.dropped_session;
  fig.link.rejected_invalid = l.rejected_invalid - link0.rejected_invalid;
  const RelayStatistics r = pair.relay_->Statistics();
  fig.relay.received = r.received - relay0.received;
  fig.relay.dropped = r.dropped - relay0.dropped;
  fig.relay.duplicated = r.duplicated - relay0.duplicated;
  fig.relay.reordered = r.reordered - relay0.reordered;
  fig.relay.spikes = r.spikes - relay0.spikes;
  return fig;
}

void PrintHeader() {
  std::printf("| case | sent by leader tick | written to DDS | DDS delivered | accepted by link | taken by follower tick | dropped stale | dropped "
              "replayed/out-of-order | rejected | taken out of order | taken older than 30 ms | max age taken (ms) "
              "| longest silence (ms) | silences > 30 ms (holds) | relay: dropped / duplicated / reordered / stalls |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
}

void PrintRow(const std::string& name, const CaseFigures& f) {
  std::printf("| %s | %llu | %llu | %llu | %llu | %llu | %llu | %llu | %llu | %llu | %llu | %.1f | %.1f | %llu | %llu / %llu / "
              "%llu / %llu |\n",
              name.c_str(), static_cast<unsigned long long>(f.sent), static_cast<unsigned long long>(f.written),
              static_cast<unsigned long long>(f.link.setpoints_received),
              static_cast<unsigned long long>(f.link.setpoints_accepted), static_cast<unsigned long long>(f.taken),
              static_cast<unsigned long long>(f.link.dropped_stale),
              static_cast<unsigned long long>(f.link.dropped_replayed),
              static_cast<unsigned long long>(f.link.rejected_invalid),
              static_cast<unsigned long long>(f.taken_out_of_order), static_cast<unsigned long long>(f.taken_too_old),
              f.max_age_ms, f.max_gap_ms, static_cast<unsigned long long>(f.gaps_over_30ms),
              static_cast<unsigned long long>(f.relay.dropped), static_cast<unsigned long long>(f.relay.duplicated),
              static_cast<unsigned long long>(f.relay.reordered), static_cast<unsigned long long>(f.relay.spikes));
  std::fflush(stdout);
}

bool Connect(RelayedPair& pair, std::uint64_t session, std::uint64_t& seq) {
  return testing::WaitFor(
      [&] {
        pair.leader_->SendSetPoint(testing::MakeSetPoint(session, ++seq, NowNs(pair.clock_)));
        return pair.follower_->Statistics().setpoints_accepted >= 10;
      },
      std::chrono::seconds(30));
}

TEST(FaultInjection, LossReorderingDuplicatesAndDelaySpikesNeverDeliverStaleOrOutOfOrderSetPoints) {
  if (!testing::CanMakeNamespaces()) GTEST_SKIP() << "needs root to make network namespaces";
  RelayedPair pair;
  std::uint64_t seq = 0;
  ASSERT_TRUE(Connect(pair, 11, seq)) << "the pair never met through the relay";
  struct Case {
    std::string name;
    RelayFaults faults;
  };
  std::vector<Case> cases;
  for (double loss : {0.0, 0.1, 0.25, 0.5}) {
    RelayFaults f;
    f.loss = loss;
    cases.push_back({"loss " + std::to_string(static_cast<int>(loss * 100)) + " %", f});
  }
  RelayFaults reorder;
  reorder.reorder = 0.2;
  cases.push_back({"reordering 20 %", reorder});
  RelayFaults dup;
  dup.duplicate = 0.2;
  cases.push_back({"duplicates 20 %", dup});
  RelayFaults spikes;
  spikes.spike_probability = 0.003;
  spikes.spike_min_s = 0.010;
  spikes.spike_max_s = 0.200;
  cases.push_back({"delay spikes 10-200 ms", spikes});
  RelayFaults all;
  all.loss = 0.1;
  all.reorder = 0.1;
  all.duplicate = 0.1;
  all.spike_probability = 0.001;
  cases.push_back({"all at once (10 % loss, reorder, dup; spikes)", all});

  PrintHeader();
  for (const auto& c : cases) {
    pair.relay_->SetFaults(c.faults);
    const CaseFigures f = Stream(pair, 11, seq, 2.0);
    pair.relay_->SetFaults({});
    PrintRow(c.name, f);
    EXPECT_EQ(f.taken_out_of_order, 0u) << c.name;
    EXPECT_EQ(f.taken_too_old, 0u) << c.name;
    EXPECT_GT(f.taken, 0u) << c.name;  // the link keeps delivering through up to 50 % loss
  }
}

TEST(FaultInjection, CapturedPacketsReplayedAreNeverAccepted) {
  if (!testing::CanMakeNamespaces()) GTEST_SKIP() << "needs root to make network namespaces";
  RelayedPair pair;
  std::uint64_t seq = 0;
  ASSERT_TRUE(Connect(pair, 21, seq)) << "the pair never met through the relay";
  pair.relay_->SetCapture(1, true);  // the leader's data traffic to the follower
  Stream(pair, 21, seq, 1.0);
  pair.relay_->SetCapture(1, false);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const FollowerLinkStatistics before = pair.follower_->Statistics();
  const std::size_t replayed = pair.relay_->Replay();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const FollowerLinkStatistics after = pair.follower_->Statistics();
  std::printf("| replay of %zu captured packets (leader silent) | accepted %llu | DDS delivered %llu | dropped replayed "
              "%llu | dropped stale %llu |\n",
              replayed, static_cast<unsigned long long>(after.setpoints_accepted - before.setpoints_accepted),
              static_cast<unsigned long long>(after.setpoints_received - before.setpoints_received),
              static_cast<unsigned long long>(after.dropped_replayed - before.dropped_replayed),
              static_cast<unsigned long long>(after.dropped_stale - before.dropped_stale));
  EXPECT_GT(replayed, 100u);  // ~1 s of set-points and their heartbeats
  EXPECT_EQ(after.setpoints_accepted, before.setpoints_accepted);
  // The replay mixed into a live stream: still only fresh, in-order set-points are taken.
  pair.relay_->SetCapture(1, true);
  Stream(pair, 21, seq, 0.5);
  pair.relay_->SetCapture(1, false);
  std::thread replayer([&] {
    for (int i = 0; i < 3; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      pair.relay_->Replay();
    }
  });
  const CaseFigures live = Stream(pair, 21, seq, 1.0);
  replayer.join();
  EXPECT_EQ(live.taken_out_of_order, 0u);
  EXPECT_EQ(live.taken_too_old, 0u);
}

}  // namespace
}  // namespace robossis::link
