// The DDS link end to end on loopback: each test starts its own participants (secured unless it says otherwise) in
// a domain of its own process, and stops them.

#include <sched.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "robossis_link.h"
#include "src/core/files.h"
#include "src/core/rt/clock.h"
#include "src/core/rt/periodic_loop.h"
#include "src/link/dds_entities.h"
#include "src/link/dds_follower_link.h"
#include "src/link/dds_leader_link.h"
#include "src/link/keys.h"
#include "src/link/wire_convert.h"
#include "src/teleop/follower_limits.h"
#include "tests/link/link_test_support.h"
#include "tests/support/alloc_counter.h"

namespace robossis::link {
namespace {

using testing::LoopbackOptions;
using testing::MakeSetPoint;
using testing::WaitFor;

std::int64_t NowNs(const rt::Clock& c) { return static_cast<std::int64_t>(std::llround(c.NowS() * 1e9)); }

// Waits until the set-points in flight have arrived: the follower's count of those it received stays the same for
// 100 ms. A fixed sleep is not enough on a loaded machine.
void AwaitArrivals(DdsFollowerLink& follower) {
  EXPECT_TRUE(WaitFor([&] {
    const std::uint64_t before = follower.Statistics().setpoints_received;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    return follower.Statistics().setpoints_received == before;
  }));
}

// Lets the set-points in flight arrive, then takes the newest, so that counters read afterwards see only what the
// test sends next.
void Settle(DdsFollowerLink& follower) {
  AwaitArrivals(follower);
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

teleop::StateCommandMessage PanelCommand(teleop::StateCommand c, std::uint64_t session, std::uint64_t sequence,
                                         std::int64_t stamp_ns) {
  teleop::StateCommandMessage m;
  m.command = c;
  m.session = session;
  m.sequence = sequence;
  m.stamp_ns = stamp_ns;
  m.source = teleop::kFromPanel;
  return m;
}

// Sends `command` (numbered from ++sequence, stamped now) every few milliseconds until the follower takes one: a
// command sent before the panel's writer has matched the follower's reader is not delivered (volatile). Returns it.
teleop::StateCommandMessage SendUntilReceived(DdsLeaderLink& panel, DdsFollowerLink& follower,
                                              teleop::StateCommandMessage command, std::uint64_t& sequence,
                                              const rt::Clock& clock) {
  teleop::StateCommandMessage received;
  EXPECT_TRUE(WaitFor([&] {
    command.sequence = ++sequence;
    command.stamp_ns = NowNs(clock);
    panel.SendCommand(command);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return follower.TakeCommand(received);
  }));
  while (follower.TakeCommand(received)) {  // the ones still in flight
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  while (follower.TakeCommand(received)) {
  }
  return received;
}

void ExpectPairExchanges(bool insecure) {
  rt::MonotonicClock clock;
  DdsFollowerLink follower(LoopbackOptions(Role::kFollower, insecure), clock);
  DdsLeaderLink leader(LoopbackOptions(Role::kLeader, insecure));
  std::uint64_t seq = 0;
  ASSERT_TRUE(StreamUntilAccepted(leader, follower, clock, 77, seq, 20));
  AwaitArrivals(follower);  // the last one sent may land after the count was reached
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
  // The stamp arrives as the status's own (n ms on the follower's clock) plus the link's one offset, the system
  // clock's from the follower's: the offset taken off, the follower's clock to the nanosecond (the leader's log
  // joins the follower's on it). Stamped at the write instead, it would be no whole millisecond.
  const std::int64_t follower_clock_ns = status.stamp_ns - follower.StatusStampOffsetNs();
  EXPECT_EQ(follower_clock_ns % 1'000'000, 0) << follower_clock_ns;
  EXPECT_GE(follower_clock_ns, 1'000'000);
  EXPECT_LE(follower_clock_ns, static_cast<std::int64_t>(n) * 1'000'000);
  EXPECT_NEAR(1e-9 * static_cast<double>(follower.StatusStampOffsetNs() + NowNs(clock) - SystemNowNs()), 0.0, 1.0);

  // State commands are the panel's.
  DdsLeaderLink panel(LoopbackOptions(Role::kPanel, insecure));
  std::uint64_t command_seq = 0;
  const teleop::StateCommandMessage received =
      SendUntilReceived(panel, follower, PanelCommand(teleop::StateCommand::kDisable, 21, 0, 0), command_seq, clock);
  EXPECT_EQ(received.command, teleop::StateCommand::kDisable);
  EXPECT_EQ(received.session, 21u);
  EXPECT_GE(received.sequence, 1u);
  EXPECT_LE(received.sequence, command_seq);
  EXPECT_GT(received.stamp_ns, 0);
  EXPECT_EQ(received.source, teleop::kFromPanel);

  // The E-stop is not a queued command: it raises the follower link's count, from the leader (the E-stop is
  // everyone's) and from the panel's "estop" command alike.
  leader.SendEStop();
  ASSERT_TRUE(WaitFor([&] { return follower.EStopsEngaged() == 1; }));
  ASSERT_TRUE(panel.SendCommand(PanelCommand(teleop::StateCommand::kEStop, 21, ++command_seq, NowNs(clock))));
  ASSERT_TRUE(WaitFor([&] { return follower.EStopsEngaged() == 2; }));
  for (teleop::StateCommandMessage queued; follower.TakeCommand(queued);) {
    EXPECT_NE(queued.command, teleop::StateCommand::kEStop);
  }
  EXPECT_EQ(follower.Statistics().estops_received, 2u);
}

TEST(DdsLink, SecuredPairExchangesSetPointsStatusAndCommands) { ExpectPairExchanges(false); }
TEST(DdsLink, InsecurePairExchangesSetPointsStatusAndCommands) { ExpectPairExchanges(true); }

// The threads that carry the set-points run below the loops and above normal-priority work, where the process may
// use SCHED_FIFO: under load a normal-priority receive thread held the set-points back past the follower's watchdog.
TEST(DdsLink, CyclonesReceiveDeliveryAndEventThreadsRunAtTheLinksRealTimePriority) {
  if (!rt::FifoPermitted(rt::kLinkThreadFifoPriority)) GTEST_SKIP() << "SCHED_FIFO is not permitted here";
  rt::MonotonicClock clock;
  DdsFollowerLink follower(LoopbackOptions(Role::kFollower, true), clock);
  std::set<std::string> fifo, other;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    std::string comm;
    std::getline(std::ifstream(task.path() / "comm"), comm);
    const pid_t tid = std::stoi(task.path().filename().string());
    sched_param param{};
    const int policy = sched_getscheduler(tid);
    sched_getparam(tid, &param);
    (policy == SCHED_FIFO && param.sched_priority == rt::kLinkThreadFifoPriority ? fifo : other).insert(comm);
  }
  for (const char* name : {"recv", "tev", "dq.user", "dq.builtins"}) EXPECT_TRUE(fifo.count(name)) << name;
  EXPECT_FALSE(fifo.count("recvUC") || other.count("recvUC"));  // one receive thread, scheduled as configured
}

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
  DdsLeaderLink panel(LoopbackOptions(Role::kPanel));
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
  leader.SendCommand(cmd);  // refused: no command writer
  panel.SendCommand(cmd);   // queued for the panel's send thread
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
  std::uint64_t seq = 0;
  ASSERT_TRUE(WaitFor([&] {
    panel_link.SendCommand(PanelCommand(teleop::StateCommand::kEStop, 5, ++seq, NowNs(clock)));
    return follower.EStopsEngaged() > 0;
  }));
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

TEST(Keys, InitMakesOneBundlePerRoleWithOnlyItsOwnKeyAndTheCaApart) {
  namespace fs = std::filesystem;
  const fs::path& dir = testing::TestKeys();
  const fs::perms owner_rw = fs::perms::owner_read | fs::perms::owner_write;
  for (const std::string role : {"leader", "follower", "panel", "observer"}) {
    std::set<std::string> files;
    for (const auto& e : fs::directory_iterator(dir / role)) files.insert(e.path().filename().string());
    EXPECT_EQ(files, (std::set<std::string>{"ca_cert.pem", "governance.p7s", "governance.xml", role + "_cert.pem",
                                             role + "_key.pem", role + "_permissions.p7s",
                                             role + "_permissions.xml"}))
        << role;
    EXPECT_EQ(fs::status(dir / role / (role + "_key.pem")).permissions(), owner_rw) << role;
    EXPECT_EQ(fs::status(dir / role).permissions(), fs::perms::owner_all) << role;
    EXPECT_NO_THROW(CheckCredentialBundle(dir / role, role == "leader"     ? Role::kLeader
                                                      : role == "follower" ? Role::kFollower
                                                      : role == "panel"    ? Role::kPanel
                                                                           : Role::kObserver));
  }
  EXPECT_EQ(fs::status(dir / kCaFolder / "ca_key.pem").permissions(), owner_rw);
  EXPECT_TRUE(fs::exists(dir / kCaFolder / "ca_cert.pem"));
  EXPECT_EQ(fs::status(dir).permissions(), fs::perms::owner_all);
  // Nothing at the top but the five folders (and the output marker): no key to copy by accident.
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_TRUE(e.is_directory() || e.path().filename().string().front() == '.') << e.path();
  }
  EXPECT_THROW(InitKeys(dir, KeysInitOptions{}), std::runtime_error);
}

TEST(Keys, DefaultValidityIsOneYear) {
  EXPECT_EQ(KeysInitOptions{}.validity_days, 365);
  // The permissions' not_after is a year after today (± the day of margin on not_before's side).
  const std::string xml = ReadTextFile(testing::TestKeys() / "leader" / "leader_permissions.xml");
  const auto at = xml.find("<not_after>");
  ASSERT_NE(at, std::string::npos);
  std::tm tm{};
  ASSERT_NE(strptime(xml.substr(at + 11, 19).c_str(), "%Y-%m-%dT%H:%M:%S", &tm), nullptr);
  const double days = std::difftime(timegm(&tm), std::time(nullptr)) / 86400.0;
  EXPECT_NEAR(days, 365.0, 1.0);
}

// A bundle made from a good one, then spoiled by `spoil`: the participant refuses it before joining.
void ExpectBundleRefused(const std::function<void(const std::filesystem::path&)>& spoil,
                         const std::string& expected_file, const std::string& expected_fix) {
  namespace fs = std::filesystem;
  const fs::path bundle = fs::temp_directory_path() / ("robossis-link-test-bundle-" + std::to_string(getpid()));
  fs::remove_all(bundle);
  fs::copy(testing::TestKeys() / "follower", bundle);
  spoil(bundle);
  LinkOptions o = LoopbackOptions(Role::kFollower);
  o.keys_dir = bundle;
  rt::MonotonicClock clock;
  try {
    DdsFollowerLink follower(o, clock);
    ADD_FAILURE() << "expected " << expected_file << " to be refused";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(expected_file), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(expected_fix), std::string::npos) << e.what();
  }
  fs::remove_all(bundle);
}

TEST(Keys, ABundleHoldingTheCaKeyIsRefused) {
  ExpectBundleRefused([](const auto& b) { std::filesystem::copy(testing::TestKeys() / kCaFolder / "ca_key.pem", b); },
                      "ca_key.pem", "offline");
}

TEST(Keys, ABundleHoldingAnotherRolesKeyIsRefused) {
  ExpectBundleRefused(
      [](const auto& b) { std::filesystem::copy(testing::TestKeys() / "leader" / "leader_key.pem", b); },
      "leader_key.pem", "remove leader_key.pem");
  // The observer's key is another role's too (a ROS 2 tool's credentials do not belong on the robot PC) ...
  ExpectBundleRefused(
      [](const auto& b) { std::filesystem::copy(testing::TestKeys() / "observer" / "observer_key.pem", b); },
      "observer_key.pem", "remove observer_key.pem");
  // ... and the observer's own bundle must not hold a unit's key.
  namespace fs = std::filesystem;
  const fs::path bundle = fs::temp_directory_path() / ("robossis-link-test-observer-" + std::to_string(getpid()));
  fs::remove_all(bundle);
  fs::copy(testing::TestKeys() / "observer", bundle);
  EXPECT_NO_THROW(CheckCredentialBundle(bundle, Role::kObserver));
  fs::copy(testing::TestKeys() / "panel" / "panel_key.pem", bundle);
  EXPECT_THROW(CheckCredentialBundle(bundle, Role::kObserver), std::runtime_error);
  fs::remove_all(bundle);
}

TEST(Keys, APrivateKeyReadableByGroupOrOthersIsRefused) {
  for (const auto extra : {std::filesystem::perms::group_read, std::filesystem::perms::others_read}) {
    ExpectBundleRefused(
        [&](const auto& b) {
          std::filesystem::permissions(b / "follower_key.pem", extra, std::filesystem::perm_options::add);
        },
        "follower_key.pem", "chmod 600");
  }
}

// What the follower acts on is decided by its access control: the leader's credentials do not grant publishing
// state_command, so a leader cannot even create the writer (Cyclone refuses it: "not allowed by security"), and a
// leader link has none: its Reset and Enable never reach the follower.
TEST(DdsLink, LeaderCredentialsCannotResetOrEnableTheFollower) {
  rt::MonotonicClock clock;
  DdsFollowerLink follower(LoopbackOptions(Role::kFollower), clock);
  DdsParticipant leader_participant(LoopbackOptions(Role::kLeader));
  try {
    leader_participant.CreateWriter(Topic::kStateCommand);
    ADD_FAILURE() << "the leader's credentials created a state_command writer";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("state_command"), std::string::npos) << e.what();
  }
  DdsLeaderLink leader(LoopbackOptions(Role::kLeader));
  std::uint64_t seq = 0;
  ASSERT_TRUE(StreamUntilAccepted(leader, follower, clock, 31, seq, 5));  // the leader is heard
  std::uint64_t command_seq = 0;
  for (int i = 0; i < 500; ++i) {  // 0.5 s of Reset and Enable while its set-points arrive
    const auto c = i % 2 ? teleop::StateCommand::kEnable : teleop::StateCommand::kReset;
    EXPECT_FALSE(leader.SendCommand(PanelCommand(c, 31, ++command_seq, NowNs(clock))));
    leader.SendSetPoint(MakeSetPoint(31, ++seq, NowNs(clock)));
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_TRUE(StreamUntilAccepted(leader, follower, clock, 31, seq, 5));  // everything sent so far has arrived
  teleop::StateCommandMessage got;
  EXPECT_FALSE(follower.TakeCommand(got));
  EXPECT_EQ(follower.Statistics().commands_received, 0u);
  EXPECT_EQ(leader.Statistics().commands_sent, 0u);
  EXPECT_EQ(leader.Statistics().commands_refused, 500u);
}

// The observer (the credentials of a ROS 2 tool) watches and commands nothing: access control refuses it a writer on
// the set-point, the state command and the E-stop (Cyclone: "Not Allowed By Security"), and grants it the status.
TEST(DdsLink, ObserverCredentialsCannotCommandTheRobot) {
  DdsParticipant observer(LoopbackOptions(Role::kObserver));
  int refused = 0;
  for (const Topic topic : {Topic::kSetPoint, Topic::kStateCommand, Topic::kEStop}) {
    try {
      observer.CreateWriter(topic);
      ADD_FAILURE() << "the observer's credentials created a writer on " << TopicName(topic);
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("Not Allowed By Security"), std::string::npos) << e.what();
      ++refused;
    }
  }
  EXPECT_EQ(refused, 3);
  for (const Topic topic : {Topic::kMeasuredCp, Topic::kMeasuredJs, Topic::kOperatingState}) {
    EXPECT_NO_THROW(observer.CreateReader(topic)) << TopicName(topic);
  }
}

// An authenticated panel's command sent again (a captured sample replayed, the same session and sequence, or an old
// stamp) is dropped and counted; only the original is applied.
TEST(DdsLink, AReplayedOrStaleResetIsRefusedAndCounted) {
  rt::MonotonicClock clock;
  DdsFollowerLink follower(LoopbackOptions(Role::kFollower), clock);
  DdsLeaderLink panel(LoopbackOptions(Role::kPanel));
  std::uint64_t seq = 0;
  teleop::StateCommandMessage got =
      SendUntilReceived(panel, follower, PanelCommand(teleop::StateCommand::kReset, 44, 0, 0), seq, clock);
  EXPECT_EQ(got.command, teleop::StateCommand::kReset);
  const auto before = follower.Statistics();
  ASSERT_EQ(before.commands_replayed + before.commands_stale, 0u);
  const teleop::StateCommandMessage reset = PanelCommand(teleop::StateCommand::kReset, 44, ++seq, NowNs(clock));
  const std::int64_t t0 = reset.stamp_ns;
  ASSERT_TRUE(panel.SendCommand(reset));
  ASSERT_TRUE(WaitFor([&] { return follower.TakeCommand(got); }));
  EXPECT_EQ(got.sequence, seq);

  ASSERT_TRUE(panel.SendCommand(reset));  // the same session and sequence
  ASSERT_TRUE(WaitFor([&] { return follower.Statistics().commands_replayed >= 1; }));
  ASSERT_TRUE(panel.SendCommand(PanelCommand(teleop::StateCommand::kReset, 44, seq + 1, t0 - 1)));  // an older stamp
  ASSERT_TRUE(WaitFor([&] { return follower.Statistics().commands_replayed >= 2; }));
  // Newer sequence and stamp, but held back: it arrives 1.5 s after it was stamped, beyond command max_age_s (1 s)
  // after the session's fastest delivery.
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ASSERT_TRUE(panel.SendCommand(PanelCommand(teleop::StateCommand::kReset, 44, seq + 2, t0 + 1)));
  ASSERT_TRUE(WaitFor([&] { return follower.Statistics().commands_stale >= 1; }));
  EXPECT_FALSE(follower.TakeCommand(got));
  // The session goes on: a fresh command is applied.
  ASSERT_TRUE(panel.SendCommand(PanelCommand(teleop::StateCommand::kEnable, 44, seq + 3, NowNs(clock))));
  ASSERT_TRUE(WaitFor([&] { return follower.TakeCommand(got); }));
  EXPECT_EQ(got.command, teleop::StateCommand::kEnable);
  const auto stats = follower.Statistics();
  EXPECT_EQ(stats.commands_replayed, 2u);
  EXPECT_EQ(stats.commands_stale, 1u);
  EXPECT_EQ(stats.commands_received, before.commands_received + 5);
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
    o.keys_dir = foreign / "leader";
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

namespace robossis::link {
namespace {

TEST(DdsLink, ALeaderWithNoFollowerGivesUpNamingTheCause) {
  DdsLeaderLink leader(LoopbackOptions(Role::kLeader));
  try {
    leader.WaitForFollower(1.0);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no follower authenticated"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no peer answered"), std::string::npos) << e.what();
  }
}

// The wait has one bound: a follower that is authenticated but never sends its state ends it there too (before, the
// first step was bounded by link.yaml's wait and --duration-s, the second by --wait-for-follower-s alone, 60 s).
TEST(DdsLink, AFollowerThatStaysSilentEndsTheLeadersWaitAtItsOneBound) {
  rt::MonotonicClock clock;
  DdsFollowerLink silent(LoopbackOptions(Role::kFollower), clock);  // publishes no state
  DdsLeaderLink leader(LoopbackOptions(Role::kLeader));
  try {
    leader.WaitForFollower(2.0);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("its operating state was not heard within 2.0 s"), std::string::npos)
        << e.what();
  }
}

// A leader whose credentials come from another CA authenticates no follower: it gives up after its wait, naming the
// handshake Cyclone refused; the leader with the right credentials started next is accepted.
TEST(DdsLink, ALeaderThatCannotAuthenticateGivesUpNamingTheRefusedHandshakeAndTheRightOneIsAccepted) {
  const std::filesystem::path foreign =
      std::filesystem::temp_directory_path() / ("robossis-link-test-rogue-" + std::to_string(getpid()));
  std::filesystem::remove_all(foreign);
  InitKeys(foreign, KeysInitOptions{});
  rt::MonotonicClock clock;
  DdsFollowerLink follower(LoopbackOptions(Role::kFollower), clock);
  std::atomic<bool> stop{false};
  std::thread status([&] {
    for (std::uint64_t i = 1; !stop.load(); ++i) {
      follower.PublishStatus(MakeStatus(i));
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  });
  {
    LinkOptions o = LoopbackOptions(Role::kLeader);
    o.keys_dir = foreign / "leader";
    DdsLeaderLink rogue(o);
    try {
      rogue.WaitForFollower(3.0);
      ADD_FAILURE() << "the rogue leader found a follower";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("no follower authenticated"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("handshake was refused"), std::string::npos) << e.what();
      std::cout << "rogue leader: " << e.what() << "\n";
    }
  }
  const auto start = std::chrono::steady_clock::now();
  DdsLeaderLink leader(LoopbackOptions(Role::kLeader));
  EXPECT_NO_THROW(leader.WaitForFollower(30.0));
  std::cout << "figures: the right leader accepted "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
            << " s after its start (after the rogue)\n";
  stop.store(true);
  status.join();
  std::filesystem::remove_all(foreign);
}

}  // namespace
}  // namespace robossis::link
