// The DDS link end to end on loopback: each test starts its own participants (secured unless it says otherwise) in
// a domain of its own process, and stops them.

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <thread>

#include <gtest/gtest.h>

#include "robossis_link.h"
#include "src/core/rt/clock.h"
#include "src/link/dds_entities.h"
#include "src/link/dds_follower_link.h"
#include "src/link/dds_leader_link.h"
#include "src/link/keys.h"
#include "src/teleop/follower_limits.h"
#include "tests/link/link_test_support.h"
#include "tests/support/alloc_counter.h"

namespace robossis::link {
namespace {

using testing::LoopbackOptions;
using testing::MakeSetPoint;
using testing::WaitFor;

std::int64_t NowNs(const rt::Clock& c) { return static_cast<std::int64_t>(std::llround(c.NowS() * 1e9)); }

// Lets the set-points in flight arrive, then takes the newest, so that counters read afterwards see only what the
// test sends next.
void Settle(DdsFollowerLink& follower) {
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  teleop::SetPointMessage m;
  std::int64_t arrival = 0;
  follower.TakeSetPoint(m, arrival);
}

// Sends set-points at ~1 kHz until the follower has accepted `count` of them (or 10 s pass).
bool StreamUntilAccepted(DdsLeaderLink& leader, DdsFollowerLink& follower, const rt::Clock& clock,
                         std::uint64_t session, std::uint64_t& sequence, std::uint64_t count) {
  const std::uint64_t target = follower.Statistics().setpoints_accepted + count;
  return WaitFor([&] {
    leader.SendSetPoint(MakeSetPoint(session, ++sequence, NowNs(clock)));
    return follower.Statistics().setpoints_accepted >= target;
  });
}

teleop::FollowerStatusMessage MakeStatus(std::uint64_t sequence) {
  teleop::FollowerStatusMessage s;
  s.sequence = sequence;
  s.stamp_ns = static_cast<std::int64_t>(sequence) * 1000000;
  s.p_FM = {0.01, -0.02, 0.284};
  s.q_FM = {0.0, 1.0, 0.0, 0.0};
  s.joints = {0.1, 0.2, 0.3, 0.28, 0.29, 0.30};
  s.effort = {1, 2, 3, 4, 5, 6};
  s.state = teleop::OperatingState::kEnabled;
  s.setpoints_accepted = 5;
  s.last_sequence = 9;
  s.limits = {.max_linear_speed_m_s = 0.01, .max_angular_speed_rad_s = 0.0175, .max_linear_accel_m_s2 = 5,
              .max_angular_accel_rad_s2 = 10.5, .max_age_s = 0.03, .model_fingerprint = 0xfeedbeef12345678ull};
  return s;
}

void ExpectPairExchanges(bool insecure) {
  rt::MonotonicClock clock;
  DdsFollowerLink follower(LoopbackOptions(Role::kFollower, insecure), clock);
  DdsLeaderLink leader(LoopbackOptions(Role::kLeader, insecure));
  std::uint64_t seq = 0;
  ASSERT_TRUE(StreamUntilAccepted(leader, follower, clock, 77, seq, 20));
  teleop::SetPointMessage got;
  std::int64_t arrival = 0;
  ASSERT_TRUE(follower.TakeSetPoint(got, arrival));
  EXPECT_EQ(got.leader_session, 77u);
  EXPECT_GT(got.sequence, 0u);
  EXPECT_DOUBLE_EQ(got.p_FM[2], 0.284);
  EXPECT_EQ(got.flags, teleop::kSetPointPresence);
  EXPECT_FALSE(follower.TakeSetPoint(got, arrival));  // taken once

  teleop::FollowerStatusMessage status;
  std::uint64_t n = 0;
  ASSERT_TRUE(WaitFor([&] {
    follower.PublishStatus(MakeStatus(++n));
    return leader.TakeFollowerStatus(status) && status.state == teleop::OperatingState::kEnabled &&
           status.joints[5] == 0.30;
  }));
  EXPECT_DOUBLE_EQ(status.p_FM[1], -0.02);
  EXPECT_DOUBLE_EQ(status.q_FM[1], 1.0);
  EXPECT_DOUBLE_EQ(status.effort[3], 4.0);
  EXPECT_EQ(status.last_sequence, 9u);
  EXPECT_EQ(teleop::CompareLimits(MakeStatus(1).limits, status.limits), "");  // the limits cross whole

  teleop::StateCommandMessage command;
  command.command = teleop::StateCommand::kEStop;
  command.sequence = 3;
  command.source = teleop::kFromLeader;
  ASSERT_TRUE(leader.SendCommand(command));
  teleop::StateCommandMessage received;
  ASSERT_TRUE(WaitFor([&] { return follower.TakeCommand(received); }));
  EXPECT_EQ(received.command, teleop::StateCommand::kEStop);
  EXPECT_EQ(received.sequence, 3u);
  EXPECT_EQ(received.source, teleop::kFromLeader);
}

TEST(DdsLink, SecuredPairExchangesSetPointsStatusAndCommands) { ExpectPairExchanges(false); }
TEST(DdsLink, InsecurePairExchangesSetPointsStatusAndCommands) { ExpectPairExchanges(true); }

// Two machines, one acceleration cap apart: the leader refuses to start, naming both values; equal, it starts.
TEST(DdsLink, ALeaderWhoseLimitsDifferFromTheFollowersRefusesToStart) {
  rt::MonotonicClock clock;
  DdsFollowerLink follower(LoopbackOptions(Role::kFollower, true), clock);
  DdsLeaderLink leader(LoopbackOptions(Role::kLeader, true));
  std::atomic<bool> done{false};
  std::thread publisher([&] {  // the follower's status stream (1 kHz on the robot)
    for (std::uint64_t n = 1; !done.load(); ++n) {
      follower.PublishStatus(MakeStatus(n));
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  });
  teleop::FollowerLimits mine = MakeStatus(1).limits;
  EXPECT_NO_THROW(teleop::CheckFollowerLimits(leader, mine, 10.0));
  mine.max_linear_accel_m_s2 = 2.5;
  std::string error;
  try {
    teleop::CheckFollowerLimits(leader, mine, 10.0);
  } catch (const std::runtime_error& e) {
    error = e.what();
  }
  done.store(true);
  publisher.join();
  EXPECT_EQ(error, "the leader refuses to start: set-point limit max_linear_accel_m_s2: the follower validates "
                   "against 5, this leader's config has 2.5 (follower.yaml/transfer.yaml must be the same on both "
                   "machines)");
}

TEST(DdsLink, RealTimeCallsAllocateNothing) {
  rt::MonotonicClock clock;
  DdsFollowerLink follower(LoopbackOptions(Role::kFollower), clock);
  DdsLeaderLink leader(LoopbackOptions(Role::kLeader));
  std::uint64_t seq = 0;
  ASSERT_TRUE(StreamUntilAccepted(leader, follower, clock, 5, seq, 5));
  teleop::SetPointMessage sp;
  teleop::FollowerStatusMessage st = MakeStatus(1);
  teleop::StateCommandMessage cmd;
  std::int64_t arrival = 0;
  robossis::testing::AllocationCounter counter;
  for (int i = 0; i < 200; ++i) {
    leader.SendSetPoint(MakeSetPoint(5, ++seq, NowNs(clock)));
    follower.TakeSetPoint(sp, arrival);
    follower.TakeCommand(cmd);
    follower.PublishStatus(st);
    leader.TakeFollowerStatus(st);
  }
  leader.SendCommand(cmd);
  EXPECT_EQ(counter.count(), 0u);
}

TEST(DdsLink, MissingCredentialsAreAnErrorNamingTheFile) {
  LinkOptions o = LoopbackOptions(Role::kFollower);
  o.keys_dir = "/nonexistent-robossis-keys";
  rt::MonotonicClock clock;
  try {
    DdsFollowerLink follower(o, clock);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("ca_cert.pem"), std::string::npos) << e.what();
  }
  o.keys_dir.clear();
  EXPECT_THROW(DdsFollowerLink(o, clock), std::runtime_error);
}

TEST(DdsLink, ParticipantWithoutCredentialsCanNeitherPublishNorRead) {
  rt::MonotonicClock clock;
  DdsFollowerLink follower(LoopbackOptions(Role::kFollower), clock);
  DdsLeaderLink leader(LoopbackOptions(Role::kLeader));
  std::uint64_t seq = 0;
  ASSERT_TRUE(StreamUntilAccepted(leader, follower, clock, 9, seq, 5));  // the secured pair works

  DdsParticipant rogue(LoopbackOptions(Role::kLeader, /*insecure=*/true));
  const dds_entity_t rogue_writer = rogue.CreateWriter(Topic::kSetPoint);
  const dds_entity_t rogue_reader = rogue.CreateReader(Topic::kSetPoint);
  const dds_entity_t rogue_state = rogue.CreateReader(Topic::kOperatingState);
  const std::uint64_t before = follower.Statistics().setpoints_received;
  robossis_msgs_msg_dds__SetPoint_ forged{};
  forged.seq = 1u << 30;
  forged.leader_session = 666;
  forged.pose.position.z = 0.284;
  forged.pose.orientation.w = 1.0;
  std::uint64_t rogue_read = 0;
  for (int i = 0; i < 1500; ++i) {  // 1.5 s of traffic both ways
    leader.SendSetPoint(MakeSetPoint(9, ++seq, NowNs(clock)));
    follower.PublishStatus(MakeStatus(static_cast<std::uint64_t>(i)));
    forged.seq++;
    forged.stamp_ns = NowNs(clock);
    dds_write(rogue_writer, &forged);
    robossis_msgs_msg_dds__SetPoint_ sample{};
    void* buf[1] = {&sample};
    dds_sample_info_t info;
    // (its own writer's samples reach its own reader: only the real leader's count)
    if (dds_take(rogue_reader, buf, &info, 1, 1) > 0 && info.valid_data && sample.leader_session != 666) ++rogue_read;
    void* loan[1] = {nullptr};
    if (dds_take(rogue_state, loan, &info, 1, 1) > 0) {
      if (info.valid_data) ++rogue_read;
      dds_return_loan(rogue_state, loan, 1);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_EQ(rogue_read, 0u);
  teleop::SetPointMessage last;
  std::int64_t arrival = 0;
  ASSERT_TRUE(follower.TakeSetPoint(last, arrival));
  EXPECT_EQ(last.leader_session, 9u);  // never the forged session
  const auto stats = follower.Statistics();
  EXPECT_GT(stats.setpoints_received, before);  // the authorised leader still arrives
  EXPECT_EQ(stats.dropped_session, 0u);          // and nothing from session 666 ever reached the filter
}

TEST(DdsLink, PanelCredentialsCannotPublishSetPoints) {
  rt::MonotonicClock clock;
  DdsFollowerLink follower(LoopbackOptions(Role::kFollower), clock);
  DdsParticipant panel(LoopbackOptions(Role::kPanel));
  // Access control refuses the writer itself: the panel's permissions grant only state_command.
  EXPECT_THROW(panel.CreateWriter(Topic::kSetPoint), std::runtime_error);
  // ... while the command topic it is granted works.
  DdsLeaderLink panel_link(LoopbackOptions(Role::kPanel));
  teleop::StateCommandMessage c;
  c.command = teleop::StateCommand::kEStop;
  c.source = 2;
  teleop::StateCommandMessage got;
  ASSERT_TRUE(WaitFor([&] {
    panel_link.SendCommand(c);
    return follower.TakeCommand(got);
  }));
  EXPECT_EQ(got.command, teleop::StateCommand::kEStop);
  EXPECT_EQ(follower.Statistics().setpoints_received, 0u);
}

TEST(DdsLink, ReplayedAndOutOfOrderSetPointsFromTheLeaderAreDroppedAndCounted) {
  rt::MonotonicClock clock;
  DdsFollowerLink follower(LoopbackOptions(Role::kFollower), clock);
  DdsLeaderLink leader(LoopbackOptions(Role::kLeader));
  std::uint64_t seq = 100;
  ASSERT_TRUE(StreamUntilAccepted(leader, follower, clock, 4, seq, 10));
  Settle(follower);
  const auto before = follower.Statistics();
  // An authenticated sender replays old sequence numbers: every one is dropped as replayed.
  for (std::uint64_t old = 1; old <= 20; ++old) {
    leader.SendSetPoint(MakeSetPoint(4, old, NowNs(clock)));
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ASSERT_TRUE(WaitFor([&] { return follower.Statistics().dropped_replayed >= before.dropped_replayed + 1; }));
  const auto after = follower.Statistics();
  EXPECT_EQ(after.setpoints_accepted, before.setpoints_accepted);
  // A set-point stamped 100 ms in the past is stale.
  leader.SendSetPoint(MakeSetPoint(4, ++seq, NowNs(clock) - 100000000));
  ASSERT_TRUE(WaitFor([&] { return follower.Statistics().dropped_stale >= 1; }));
  EXPECT_EQ(follower.Statistics().setpoints_accepted, before.setpoints_accepted);
}

TEST(DdsLink, NanAndHugeSetPointsFromAnAuthenticatedLeaderAreRejectedAndCounted) {
  rt::MonotonicClock clock;
  DdsFollowerLink follower(LoopbackOptions(Role::kFollower), clock);
  DdsLeaderLink leader(LoopbackOptions(Role::kLeader));
  std::uint64_t seq = 0;
  ASSERT_TRUE(StreamUntilAccepted(leader, follower, clock, 8, seq, 5));
  Settle(follower);
  std::int64_t arrival = 0;
  const auto before = follower.Statistics();
  for (int i = 0; i < 40; ++i) {
    teleop::SetPointMessage bad = MakeSetPoint(8, ++seq, NowNs(clock));
    if (i % 4 == 0) bad.p_FM[0] = std::numeric_limits<double>::quiet_NaN();
    if (i % 4 == 1) bad.p_FM[2] = 1e300;
    if (i % 4 == 2) bad.twist_F[3] = std::numeric_limits<double>::infinity();
    if (i % 4 == 3) bad.q_FM = {2, 0, 0, 0};
    leader.SendSetPoint(bad);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ASSERT_TRUE(WaitFor([&] { return follower.Statistics().rejected_invalid >= before.rejected_invalid + 1; }));
  EXPECT_EQ(follower.Statistics().setpoints_accepted, before.setpoints_accepted);
  teleop::SetPointMessage after;
  EXPECT_FALSE(follower.TakeSetPoint(after, arrival));  // nothing new reached the follower unit
}

}  // namespace
}  // namespace robossis::link

namespace robossis::link {
namespace {

TEST(Keys, InitMakesEveryCredentialWithPrivateKeysOwnerOnlyAndRefusesToOverwrite) {
  const std::filesystem::path& dir = testing::TestKeys();
  for (const char* role : {"leader", "follower", "panel"}) {
    for (const std::string suffix : {"_cert.pem", "_key.pem", "_permissions.p7s"}) {
      EXPECT_TRUE(std::filesystem::exists(dir / (role + suffix))) << role << suffix;
    }
    const auto perms = std::filesystem::status(dir / (std::string(role) + "_key.pem")).permissions();
    EXPECT_EQ(perms, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write) << role;
  }
  EXPECT_TRUE(std::filesystem::exists(dir / "governance.p7s"));
  EXPECT_EQ(std::filesystem::status(dir / "ca_key.pem").permissions(),
            std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
  EXPECT_EQ(std::filesystem::status(dir).permissions(), std::filesystem::perms::owner_all);
  EXPECT_THROW(InitKeys(dir, KeysInitOptions{}), std::runtime_error);
}

}  // namespace
}  // namespace robossis::link

namespace robossis::link {
namespace {

TEST(DdsLinkRestart, ARestartedLeaderIsANewSessionAndARestartedFollowerHearsTheLeaderAgain) {
  rt::MonotonicClock clock;
  auto follower = std::make_unique<DdsFollowerLink>(LoopbackOptions(Role::kFollower), clock);
  auto leader = std::make_unique<DdsLeaderLink>(LoopbackOptions(Role::kLeader));
  std::uint64_t seq = 0;
  auto stream = [&](std::uint64_t session, std::uint64_t count) {
    const std::uint64_t target = follower->Statistics().setpoints_accepted + count;
    return WaitFor([&] {
      leader->SendSetPoint(MakeSetPoint(session, ++seq, NowNs(clock)));
      return follower->Statistics().setpoints_accepted >= target;
    });
  };
  ASSERT_TRUE(stream(1, 10));
  // The leader process goes away (its participant with it) and a new one starts: a new session, from sequence 1.
  leader.reset();
  leader = std::make_unique<DdsLeaderLink>(LoopbackOptions(Role::kLeader));
  seq = 0;
  ASSERT_TRUE(stream(2, 10));
  teleop::SetPointMessage m;
  std::int64_t arrival = 0;
  ASSERT_TRUE(WaitFor([&] { return follower->TakeSetPoint(m, arrival) && m.leader_session == 2; }));
  // The follower goes away and comes back while the leader keeps sending.
  follower.reset();
  follower = std::make_unique<DdsFollowerLink>(LoopbackOptions(Role::kFollower), clock);
  ASSERT_TRUE(stream(2, 10));
  // ... and an old session replayed after the restart is refused once the new one runs.
  ASSERT_TRUE(stream(3, 5));
  const auto before = follower->Statistics();
  for (int i = 0; i < 10; ++i) {
    leader->SendSetPoint(MakeSetPoint(2, ++seq, NowNs(clock)));
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_TRUE(WaitFor([&] { return follower->Statistics().dropped_session > before.dropped_session; }));
}

}  // namespace
}  // namespace robossis::link

namespace robossis::link {
namespace {

TEST(DdsLink, ALeaderWithCredentialsFromAnotherCaIsNotHeard) {
  const std::filesystem::path foreign =
      std::filesystem::temp_directory_path() / ("robossis-link-test-foreign-" + std::to_string(getpid()));
  std::filesystem::remove_all(foreign);
  InitKeys(foreign, KeysInitOptions{});  // a valid set of credentials, signed by a different CA
  {
    rt::MonotonicClock clock;
    DdsFollowerLink follower(LoopbackOptions(Role::kFollower), clock);
    LinkOptions o = LoopbackOptions(Role::kLeader);
    o.keys_dir = foreign;
    DdsLeaderLink impostor(o);
    for (std::uint64_t i = 1; i <= 1500; ++i) {  // 1.5 s
      impostor.SendSetPoint(MakeSetPoint(13, i, NowNs(clock)));
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    EXPECT_EQ(follower.Statistics().setpoints_received, 0u);
    EXPECT_EQ(impostor.Statistics().followers_matched, 0u);
  }
  std::filesystem::remove_all(foreign);
}

}  // namespace
}  // namespace robossis::link
