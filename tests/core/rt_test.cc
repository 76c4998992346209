// The real-time helpers: the single-producer queue and the snapshot hand over values between threads without
// losing, tearing or reordering them; the simulated clock is exact.

#include <array>
#include <atomic>
#include <cstdint>
#include <thread>

#include <gtest/gtest.h>

#include "src/core/rt/clock.h"
#include "src/core/rt/snapshot.h"
#include "src/core/rt/spsc_queue.h"
#include "tests/support/alloc_counter.h"

namespace robossis::rt {
namespace {

TEST(SpscQueueTest, RefusesWhenFullAndKeepsOrder) {
  SpscQueue<int> q(3);  // rounded up to 4
  EXPECT_EQ(q.capacity(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(q.TryPush(i));
  EXPECT_FALSE(q.TryPush(99));
  int v = -1;
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(q.TryPop(v));
    EXPECT_EQ(v, i);
  }
  EXPECT_FALSE(q.TryPop(v));
}

TEST(SpscQueueTest, HandsOverEveryValueAcrossThreadsInOrder) {
  SpscQueue<std::uint64_t> q(64);
  constexpr std::uint64_t kCount = 200000;
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kCount;) {
      if (q.TryPush(i)) ++i;
    }
  });
  std::uint64_t expected = 0, v = 0;
  while (expected < kCount) {
    if (q.TryPop(v)) {
      ASSERT_EQ(v, expected);
      ++expected;
    }
  }
  producer.join();
}

TEST(SpscQueueTest, PushAndPopDoNotAllocate) {
  SpscQueue<std::array<double, 8>> q(16);
  std::array<double, 8> v{};
  testing::AllocationCounter counter;
  for (int i = 0; i < 100; ++i) {
    q.TryPush(v);
    q.TryPop(v);
  }
  EXPECT_EQ(counter.count(), 0u);
}

struct Record {
  std::uint64_t a = 0;
  std::array<double, 12> payload{};
  std::uint64_t b = 0;
};

TEST(SnapshotTest, ReadersNeverSeeATornRecord) {
  Snapshot<Record> snap;
  Record out;
  EXPECT_FALSE(snap.Read(out));
  std::atomic<bool> stop{false};
  std::thread writer([&] {
    Record r;
    for (std::uint64_t i = 1; !stop.load(); ++i) {
      r.a = r.b = i;
      r.payload.fill(static_cast<double>(i));
      snap.Publish(r);
    }
  });
  std::uint64_t last = 0;
  for (int reads = 0; reads < 100000;) {
    if (!snap.Read(out)) continue;  // the writer has not published yet
    ++reads;
    ASSERT_EQ(out.a, out.b);
    for (double x : out.payload) ASSERT_EQ(x, static_cast<double>(out.a));
    ASSERT_GE(out.a, last);  // never older than a value already seen
    last = out.a;
  }
  stop = true;
  writer.join();
  EXPECT_GT(snap.version(), 0u);
}

TEST(SnapshotTest, ReadNewerHandsEachValueOutOnceAndNeverAnOlderOne) {
  // The "latest value" hand-over of the links: a consumer taking set-points while the producer publishes. Each
  // value read must be strictly newer than the one before (a duplicate would be a set-point taken twice).
  Snapshot<Record> snap;
  Record out;
  std::uint64_t held = 0;
  EXPECT_FALSE(snap.ReadNewer(out, held));
  // The writer publishes a fixed number of values, pausing briefly between them as a loop publishing at its rate
  // does; the reader takes what it can meanwhile. (A writer publishing back to back can starve a seqlock's reader
  // for minutes, so the run is bounded by the writer, never by how many the reader manages to take.)
  constexpr std::uint64_t kPublishes = 200000;
  std::atomic<bool> done{false};
  std::thread writer([&] {
    Record r;
    for (std::uint64_t i = 1; i <= kPublishes; ++i) {
      r.a = r.b = i;
      snap.Publish(r);
      for (int spin = 0; spin < 200; ++spin) std::atomic_signal_fence(std::memory_order_seq_cst);
    }
    done = true;
  });
  std::uint64_t last = 0;
  while (!done.load()) {
    if (!snap.ReadNewer(out, held)) continue;
    ASSERT_EQ(out.a, out.b);
    ASSERT_GT(out.a, last);  // the i-th publish is version i: the value and the version agree
    ASSERT_EQ(held, out.a);
    last = out.a;
  }
  writer.join();
  snap.ReadNewer(out, held);                 // the writer's last value, if not taken yet
  EXPECT_EQ(held, kPublishes);               // every publish counted as one version
  EXPECT_FALSE(snap.ReadNewer(out, held));  // nothing published since: nothing newer
}

}  // namespace

// Stops a writer between the two halves of a publish, where a preemption could stop it.
class SnapshotTestAccess {
 public:
  template <typename T>
  static void BeginPublish(Snapshot<T>& snap, const T& value) noexcept { snap.BeginPublish(value); }
  template <typename T>
  static void EndPublish(Snapshot<T>& snap, const T& value) noexcept { snap.EndPublish(value); }
};

namespace {

TEST(SnapshotTest, AWriterStoppedInTheMiddleOfAWriteNeverHoldsAReader) {
  // A SCHED_FIFO loop that preempts a normal-priority writer (a link's receive thread) in the middle of a write, on
  // the writer's CPU, keeps it from finishing for as long as the loop's thread holds the CPU. The reader must get
  // the last complete value at once. (A sequence lock's reader spins here for ever: this test then never ends.)
  Snapshot<Record> snap;
  Record first, second, out;
  first.a = first.b = 1;
  second.a = second.b = 2;
  std::uint64_t held = 0;
  SnapshotTestAccess::BeginPublish(snap, first);
  EXPECT_FALSE(snap.Read(out));  // stopped in the first write: nothing complete yet
  EXPECT_FALSE(snap.ReadNewer(out, held));
  SnapshotTestAccess::EndPublish(snap, first);
  ASSERT_TRUE(snap.ReadNewer(out, held));
  EXPECT_EQ(out.a, 1u);
  EXPECT_EQ(held, 1u);
  SnapshotTestAccess::BeginPublish(snap, second);
  EXPECT_FALSE(snap.ReadNewer(out, held));  // nothing newer is complete
  ASSERT_TRUE(snap.Read(out));              // the previous value, whole
  EXPECT_EQ(out.a, 1u);
  EXPECT_EQ(out.b, 1u);
  EXPECT_EQ(snap.version(), 1u);
  SnapshotTestAccess::EndPublish(snap, second);
  ASSERT_TRUE(snap.ReadNewer(out, held));
  EXPECT_EQ(out.a, 2u);
  EXPECT_EQ(held, 2u);
  EXPECT_EQ(snap.version(), 2u);
}

TEST(SnapshotTest, PublishAndReadDoNotAllocate) {
  Snapshot<Record> snap;
  Record r, out;
  testing::AllocationCounter counter;
  for (int i = 0; i < 100; ++i) {
    snap.Publish(r);
    snap.Read(out);
  }
  EXPECT_EQ(counter.count(), 0u);
}

TEST(ClockTest, SimulatedClockIsExactAndMonotonicClockAdvances) {
  SimulatedClock sim;
  for (int i = 0; i < 1000; ++i) sim.AdvanceNs(250'000);  // 4 kHz ticks
  EXPECT_EQ(sim.now_ns(), 250'000'000);
  EXPECT_DOUBLE_EQ(sim.NowS(), 0.25);
  MonotonicClock mono;
  const double t0 = mono.NowS();
  std::this_thread::sleep_for(std::chrono::milliseconds(2));
  EXPECT_GT(mono.NowS(), t0);
  EXPECT_GE(t0, 0.0);
}

}  // namespace
}  // namespace robossis::rt
