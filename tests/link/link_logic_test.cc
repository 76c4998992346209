// The link's pure logic: set-point and command freshness, the sanity check, the wire mapping, the permissions documents.

#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "src/link/command_freshness.h"
#include "src/link/keys.h"
#include "src/link/setpoint_freshness.h"
#include "src/link/setpoint_validation.h"
#include "src/link/wire_convert.h"
#include "tests/support/alloc_counter.h"

namespace robossis::link {
namespace {

constexpr std::int64_t kMs = 1000000;

teleop::SetPointMessage At(std::uint64_t session, std::uint64_t seq, std::int64_t stamp_ns) {
  teleop::SetPointMessage m;
  m.leader_session = session;
  m.sequence = seq;
  m.stamp_ns = stamp_ns;
  m.p_FM = {0.0, 0.0, 0.284};
  return m;
}

SetPointFreshness Filter() { return SetPointFreshness(30 * kMs, 30 * kMs, 1e-4); }

TEST(SetPointFreshness, AcceptsAnIncreasingStreamWithAClockOffset) {
  auto f = Filter();
  const std::int64_t offset = 123456789 * kMs;  // the two clocks share no epoch
  for (std::uint64_t i = 1; i <= 100; ++i) {
    EXPECT_EQ(f.Check(At(7, i, static_cast<std::int64_t>(i) * kMs), offset + static_cast<std::int64_t>(i) * kMs),
              Freshness::kAccepted);
  }
}

TEST(SetPointFreshness, DropsDuplicatesAndOlderSequences) {
  auto f = Filter();
  EXPECT_EQ(f.Check(At(7, 10, 10 * kMs), 10 * kMs), Freshness::kAccepted);
  EXPECT_EQ(f.Check(At(7, 10, 10 * kMs), 11 * kMs), Freshness::kReplayed);
  EXPECT_EQ(f.Check(At(7, 9, 9 * kMs), 11 * kMs), Freshness::kReplayed);
  EXPECT_EQ(f.Check(At(7, 12, 12 * kMs), 12 * kMs), Freshness::kAccepted);
  EXPECT_EQ(f.Check(At(7, 11, 11 * kMs), 12 * kMs), Freshness::kReplayed);  // reordered behind 12
}

TEST(SetPointFreshness, DropsASetPointDelayedBeyondTheAgeLimit) {
  auto f = Filter();
  EXPECT_EQ(f.Check(At(7, 1, 1 * kMs), 2 * kMs), Freshness::kAccepted);
  EXPECT_EQ(f.Check(At(7, 2, 2 * kMs), 2 * kMs + 29 * kMs), Freshness::kAccepted);  // 29 ms late: still fresh
  EXPECT_EQ(f.Check(At(7, 3, 3 * kMs), 3 * kMs + 32 * kMs), Freshness::kStale);     // 31 ms late
  EXPECT_EQ(f.Check(At(7, 4, 40 * kMs), 41 * kMs), Freshness::kAccepted);
}

TEST(SetPointFreshness, AbsorbsSlowClockDrift) {
  auto f = Filter();
  // The follower's clock runs 50 ppm fast for 1000 s: 50 ms of drift, absorbed by the 100 ppm allowance.
  for (std::int64_t i = 1; i <= 1000; ++i) {
    const std::int64_t stamp = i * 1000 * kMs;
    const std::int64_t arrival = stamp + stamp / 20000 + kMs;
    ASSERT_EQ(f.Check(At(7, static_cast<std::uint64_t>(i), stamp), arrival), Freshness::kAccepted) << i;
  }
}

TEST(SetPointFreshness, TakesANewSessionOnlyAfterTheOldOneWentSilentAndNeverGoesBack) {
  auto f = Filter();
  EXPECT_EQ(f.Check(At(1, 100, 100 * kMs), 100 * kMs), Freshness::kAccepted);
  EXPECT_EQ(f.Check(At(2, 1, 5 * kMs), 110 * kMs), Freshness::kConcurrentSession);  // session 1 still talking
  EXPECT_EQ(f.Check(At(2, 2, 6 * kMs), 131 * kMs), Freshness::kAccepted);          // 31 ms of silence
  EXPECT_EQ(f.current_session(), 2u);
  EXPECT_EQ(f.Check(At(1, 101, 101 * kMs), 200 * kMs), Freshness::kRetiredSession);  // a replay of the old leader
  EXPECT_EQ(f.Check(At(2, 3, 7 * kMs), 132 * kMs), Freshness::kAccepted);
}

TEST(SetPointFreshness, StampsAndArrivalsAtTheEndsOfInt64NeverOverflow) {
  constexpr std::int64_t kMin = std::numeric_limits<std::int64_t>::min();
  constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
  SetPointFreshness f = Filter();
  EXPECT_EQ(f.Check(At(7, 1, 0), 0), Freshness::kAccepted);
  // A stamp from the far past arrives 1 ms later: its (arrival - stamp) is beyond int64, and saturates to a delay
  // far beyond the age limit (a wrapped difference would look like the fastest delivery yet).
  EXPECT_EQ(f.Check(At(7, 2, kMin), 1 * kMs), Freshness::kStale);
  EXPECT_EQ(f.Check(At(7, 3, 2 * kMs), 2 * kMs), Freshness::kAccepted);  // the session goes on
  // A new session at the ends of the clock, both ways, then an ordinary set-point: verdicts, not undefined behaviour.
  SetPointFreshness g = Filter();
  EXPECT_EQ(g.Check(At(8, 1, kMax), kMin), Freshness::kAccepted);
  EXPECT_EQ(g.Check(At(8, 2, kMin), kMax), Freshness::kStale);
  EXPECT_EQ(g.Check(At(9, 1, 0), kMax), Freshness::kAccepted);  // the old session silent for the whole clock
  EXPECT_EQ(g.Check(At(9, 2, kMax), kMin), Freshness::kAccepted);  // saturated: as fast as the fastest yet
}

TEST(SetPointFreshness, CheckAllocatesNothing) {
  auto f = Filter();
  testing::AllocationCounter counter;
  for (std::uint64_t i = 1; i <= 100; ++i) f.Check(At(3, i, static_cast<std::int64_t>(i) * kMs), static_cast<std::int64_t>(i) * kMs);
  EXPECT_EQ(counter.count(), 0u);
}

teleop::StateCommandMessage Command(std::uint64_t session, std::uint64_t seq, std::int64_t stamp_ns) {
  teleop::StateCommandMessage m;
  m.command = teleop::StateCommand::kReset;
  m.session = session;
  m.sequence = seq;
  m.stamp_ns = stamp_ns;
  return m;
}

CommandFilter Commands() { return CommandFilter(1000 * kMs, 1e-4); }

TEST(CommandFilter, AcceptsEachSessionsIncreasingCommandsWithAnyClockOffset) {
  auto f = Commands();
  const std::int64_t offset = 987654321 * kMs;
  EXPECT_EQ(f.Check(Command(5, 1, 10 * kMs), offset + 11 * kMs), CommandFreshness::kAccepted);
  EXPECT_EQ(f.Check(Command(6, 1, -50 * kMs), 12 * kMs), CommandFreshness::kAccepted);  // another panel, its clock
  EXPECT_EQ(f.Check(Command(5, 2, 500 * kMs), offset + 502 * kMs), CommandFreshness::kAccepted);
  EXPECT_EQ(f.Check(Command(6, 2, 900 * kMs), 963 * kMs), CommandFreshness::kAccepted);
}

TEST(CommandFilter, DropsTheSameSessionAndSequenceAndAnOlderStampAsReplayed) {
  auto f = Commands();
  EXPECT_EQ(f.Check(Command(5, 7, 100 * kMs), 101 * kMs), CommandFreshness::kAccepted);
  EXPECT_EQ(f.Check(Command(5, 7, 100 * kMs), 300 * kMs), CommandFreshness::kReplayed);  // captured and sent again
  EXPECT_EQ(f.Check(Command(5, 6, 90 * kMs), 300 * kMs), CommandFreshness::kReplayed);   // an older one
  EXPECT_EQ(f.Check(Command(5, 8, 100 * kMs), 300 * kMs), CommandFreshness::kReplayed);  // the old stamp
  EXPECT_EQ(f.Check(Command(5, 8, 200 * kMs), 201 * kMs), CommandFreshness::kAccepted);
}

TEST(CommandFilter, DropsACommandDelayedBeyondTheAgeLimit) {
  auto f = Commands();
  EXPECT_EQ(f.Check(Command(5, 1, 0), 2 * kMs), CommandFreshness::kAccepted);
  EXPECT_EQ(f.Check(Command(5, 2, 10 * kMs), 10 * kMs + 1001 * kMs), CommandFreshness::kAccepted);  // 999 ms late
  EXPECT_EQ(f.Check(Command(5, 3, 20 * kMs), 20 * kMs + 1003 * kMs), CommandFreshness::kStale);     // 1001 ms late
  EXPECT_EQ(f.Check(Command(5, 4, 2000 * kMs), 2003 * kMs), CommandFreshness::kAccepted);
}

TEST(CommandFilter, RemembersTheLastSessionsAndAllocatesNothing) {
  auto f = Commands();
  ASSERT_EQ(f.Check(Command(1, 3, 0), 0), CommandFreshness::kAccepted);
  testing::AllocationCounter counter;
  for (std::uint64_t s = 2; s <= kCommandSessions; ++s) {
    ASSERT_EQ(f.Check(Command(s, 1, 0), 0), CommandFreshness::kAccepted);
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_EQ(f.Check(Command(1, 3, 0), 0), CommandFreshness::kReplayed);  // the first session is still known
}

TEST(SetPointValidation, AcceptsASaneSetPointAndNamesTheFirstBadField) {
  LinkTuning t;
  teleop::SetPointMessage m = At(1, 1, 0);
  const char* why = "unset";
  EXPECT_TRUE(IsSaneSetPoint(m, t, &why));
  EXPECT_EQ(why, nullptr);
  m.p_FM[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(IsSaneSetPoint(m, t, &why));
  EXPECT_STREQ(why, "p_FM not finite");
  m = At(1, 1, 0);
  m.p_FM[0] = 1e300;
  EXPECT_FALSE(IsSaneSetPoint(m, t, &why));
  EXPECT_STREQ(why, "p_FM beyond max_position_m");
  m = At(1, 1, 0);
  m.q_FM = {1, 0.2, 0, 0};
  EXPECT_FALSE(IsSaneSetPoint(m, t, &why));
  EXPECT_STREQ(why, "q_FM not a unit quaternion");
  m = At(1, 1, 0);
  m.twist_F[4] = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(IsSaneSetPoint(m, t, &why));
  EXPECT_STREQ(why, "twist_F not finite");
  m = At(1, 1, 0);
  m.twist_F[2] = 5.0;
  EXPECT_FALSE(IsSaneSetPoint(m, t, &why));
  EXPECT_STREQ(why, "twist_F linear beyond max_linear_speed_m_per_s");
}

TEST(WireConvert, SetPointRoundTripsAndQuaternionIsReorderedForRos) {
  teleop::SetPointMessage m = At(0xABCDEF, 42, -5);
  m.q_FM = {0.5, 0.5, -0.5, 0.5};
  m.twist_F = {1, 2, 3, 4, 5, 6};
  m.flags = teleop::kSetPointClutched | (1u << 5);  // a flag bit the wire has no boolean for still travels
  robossis_msgs_msg_dds__SetPoint_ w{};
  ToWire(m, w);
  EXPECT_EQ(w.pose.orientation.w, 0.5);
  EXPECT_EQ(w.pose.orientation.y, -0.5);
  EXPECT_TRUE(w.clutch);
  EXPECT_FALSE(w.presence);
  teleop::SetPointMessage back;
  FromWire(w, back);
  EXPECT_EQ(back.sequence, 42u);
  EXPECT_EQ(back.leader_session, 0xABCDEFu);
  EXPECT_EQ(back.stamp_ns, -5);
  EXPECT_EQ(back.q_FM, m.q_FM);
  EXPECT_EQ(back.twist_F, m.twist_F);
  EXPECT_EQ(back.flags, m.flags);
}

// A disabled, unhomed follower that refused an enable: the homed flag (is_homed, the back end's own) and the
// refusal's reason cross the wire.
TEST(WireConvert, TheHomedFlagAndANotHomedRefusalTravel) {
  teleop::FollowerStatusMessage m;
  m.state = teleop::OperatingState::kDisabled;
  m.fault_reason = teleop::FaultReason::kNotHomed;
  char frame_id[] = "F";
  robossis_msgs_msg_dds__OperatingState_ w{};
  for (bool homed : {false, true}) {
    m.homed = homed;
    ToOperatingState(m, 0, frame_id, w);
    EXPECT_EQ(w.is_homed, homed);
    teleop::FollowerStatusMessage back;
    FromOperatingState(w, back);
    EXPECT_EQ(back.homed, homed);
    EXPECT_EQ(back.fault_reason, teleop::FaultReason::kNotHomed);
    EXPECT_EQ(back.state, teleop::OperatingState::kDisabled);
  }
}

// The follower's load and its port's energies cross the wire for the leader's bilateral feedback; a source byte this
// version does not know is no wrench (the leader shows none).
TEST(WireConvert, TheWrenchAndThePortEnergiesRoundTrip) {
  teleop::FollowerStatusMessage m;
  m.wrench_F = {517, -20, 3, 74, 0.5, -2};
  m.wrench_source = teleop::WrenchSource::kDriveEfforts;
  m.port_energy_in_j = 1.25;
  m.port_energy_out_j = 3.5;
  char frame_id[] = "rsr_fixed";
  robossis_msgs_msg_dds__OperatingState_ w{};
  ToOperatingState(m, 0, frame_id, w);
  teleop::FollowerStatusMessage back;
  FromOperatingState(w, back);
  EXPECT_EQ(back.wrench_F, m.wrench_F);
  EXPECT_EQ(back.wrench_source, teleop::WrenchSource::kDriveEfforts);
  EXPECT_EQ(back.port_energy_in_j, 1.25);
  EXPECT_EQ(back.port_energy_out_j, 3.5);
  w.wrench_source = 200;
  FromOperatingState(w, back);
  EXPECT_EQ(back.wrench_source, teleop::WrenchSource::kNone);
}

// The hand's energy crosses the wire with every set-point, for the follower's half of the network form.
TEST(WireConvert, TheSetPointCarriesTheHandsEnergyAndItsFlag) {
  teleop::SetPointMessage m;
  m.flags = teleop::kSetPointPresence | teleop::kSetPointEnergyBudget;
  m.hand_energy_in_j = 2.75;
  robossis_msgs_msg_dds__SetPoint_ w{};
  ToWire(m, w);
  teleop::SetPointMessage back;
  FromWire(w, back);
  EXPECT_EQ(back.hand_energy_in_j, 2.75);
  EXPECT_EQ(back.flags, m.flags);
}

TEST(WireConvert, TimeSplitsIntoSecondsAndNanoseconds) {
  const auto t = ToTime(3 * 1000000000LL + 7);
  EXPECT_EQ(t.sec, 3);
  EXPECT_EQ(t.nanosec, 7u);
  EXPECT_EQ(FromTime(t), 3 * 1000000000LL + 7);
  EXPECT_EQ(FromTime(ToTime(-1)), -1);
}

TEST(WireConvert, CommandAndStateNamesRoundTrip) {
  for (auto c : {teleop::StateCommand::kEnable, teleop::StateCommand::kDisable, teleop::StateCommand::kHome,
                 teleop::StateCommand::kEStop, teleop::StateCommand::kReset}) {
    teleop::StateCommand back = teleop::StateCommand::kDisable;
    ASSERT_TRUE(ParseCommandName(CommandName(c), back));
    EXPECT_EQ(back, c);
  }
  teleop::StateCommand unused;
  EXPECT_FALSE(ParseCommandName("launch", unused));
  EXPECT_FALSE(ParseCommandName(nullptr, unused));
  teleop::OperatingState s;
  ASSERT_TRUE(ParseOperatingStateName(OperatingStateName(teleop::OperatingState::kClutched), s));
  EXPECT_EQ(s, teleop::OperatingState::kClutched);
}

TEST(Permissions, EachRoleIsGrantedOnlyItsOwnTopics) {
  const auto leader = TopicsOf(Role::kLeader, "rsr");
  const auto panel = TopicsOf(Role::kPanel, "rsr");
  const auto follower = TopicsOf(Role::kFollower, "rsr");
  auto has = [](const std::vector<std::string>& v, const std::string& s) {
    return std::find(v.begin(), v.end(), s) != v.end();
  };
  EXPECT_TRUE(has(leader.publish, "rt/rsr/setpoint"));
  // Enable, reset, home: the panel's, never the leader's (it sends set-points, and the E-stop everyone may give).
  EXPECT_EQ(leader.publish, (std::vector<std::string>{"rt/rsr/setpoint", "rt/rsr/estop"}));
  EXPECT_TRUE(has(panel.publish, "rt/rsr/estop"));
  EXPECT_TRUE(has(follower.subscribe, "rt/rsr/estop"));
  EXPECT_FALSE(has(follower.publish, "rt/rsr/estop"));
  EXPECT_TRUE(has(follower.subscribe, "rt/rsr/state_command"));
  EXPECT_FALSE(has(panel.publish, "rt/rsr/setpoint"));
  EXPECT_TRUE(has(panel.publish, "rt/rsr/state_command"));
  EXPECT_FALSE(has(leader.publish, "rt/rsr/measured_cp"));
  EXPECT_TRUE(has(follower.publish, "rt/rsr/measured_cp"));
  EXPECT_TRUE(has(follower.subscribe, "rt/rsr/setpoint"));
  const std::string xml = PermissionsXml(Role::kPanel, "CN=panel,O=Robossis,C=US", "rsr", "2026-01-01T00:00:00",
                                         "2036-01-01T00:00:00");
  EXPECT_EQ(xml.find("rt/rsr/setpoint"), std::string::npos);
  EXPECT_NE(xml.find("<default>DENY</default>"), std::string::npos);
  EXPECT_NE(xml.find("CN=panel,O=Robossis,C=US"), std::string::npos);
}

// The observer (a ROS 2 tool) may read the status and ROS 2's own topics, and publish nothing under rt/rsr/.
TEST(Permissions, TheObserverReadsTheStatusAndPublishesNothingOfTheRobots) {
  const auto observer = TopicsOf(Role::kObserver, "rsr");
  for (const auto& t : observer.publish) EXPECT_NE(t.rfind("rt/rsr/", 0), 0u) << t;
  for (const auto& t : observer.publish) EXPECT_NE(t.rfind("rt/*", 0), 0u) << t;  // no wildcard over rt/rsr/
  for (const std::string t : {"rt/rsr/measured_cp", "rt/rsr/measured_js", "rt/rsr/operating_state"}) {
    EXPECT_NE(std::find(observer.subscribe.begin(), observer.subscribe.end(), t), observer.subscribe.end()) << t;
  }
  for (const std::string t : {"ros_discovery_info", "rt/rosout", "rt/parameter_events"}) {
    EXPECT_NE(std::find(observer.publish.begin(), observer.publish.end(), t), observer.publish.end()) << t;
    EXPECT_NE(std::find(observer.subscribe.begin(), observer.subscribe.end(), t), observer.subscribe.end()) << t;
  }
}

TEST(Permissions, HostileNamespacesAreRefusedAndValuesEscaped) {
  for (const std::string& ns : std::vector<std::string>{"*", "rsr</topic><topic>*", "", "rsr<x>", "rs?r", "rsr/other",
                                                        "rsr*", std::string(kMaxTopicNamespaceLength + 1, 'a')}) {
    EXPECT_THROW(TopicsOf(Role::kLeader, ns), std::invalid_argument) << ns;
    EXPECT_THROW(PermissionsXml(Role::kLeader, "CN=leader", ns, "a", "b"), std::invalid_argument) << ns;
    KeysInitOptions options;
    options.topic_namespace = ns;
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "robossis-keys-hostile-ns";
    std::filesystem::remove_all(dir);
    EXPECT_THROW(InitKeys(dir, options), std::invalid_argument) << ns;
    EXPECT_FALSE(std::filesystem::exists(dir)) << ns;
  }
  EXPECT_NO_THROW(TopicsOf(Role::kLeader, std::string(kMaxTopicNamespaceLength, 'a')));
  EXPECT_EQ(KeysInitOptions{}.topic_namespace, LinkOptions{}.topic_namespace);
  const std::string xml = PermissionsXml(Role::kLeader, "CN=a<b>&\"c", kTopicNamespace, "x<", "y&");
  EXPECT_NE(xml.find("CN=a&lt;b&gt;&amp;&quot;c"), std::string::npos);
  EXPECT_NE(xml.find("x&lt;"), std::string::npos);
  EXPECT_NE(xml.find("y&amp;"), std::string::npos);
}

TEST(KeysInitOptionsTest, AnOrganisationThatWouldAddSubjectFieldsOrAnAbsurdValidityIsRefusedBeforeAnythingIsWritten) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "robossis-keys-hostile-options";
  std::filesystem::remove_all(dir);
  for (const std::string& org : std::vector<std::string>{"", "X/CN=leader", "A=B", "A,B", "A+B", "\\", "A\nB",
                                                         std::string(kMaxOrganisationLength + 1, 'a')}) {
    KeysInitOptions options;
    options.organisation = org;
    EXPECT_THROW(ValidateKeysInitOptions(options), std::invalid_argument) << org;
    EXPECT_THROW(InitKeys(dir, options), std::invalid_argument) << org;
    EXPECT_FALSE(std::filesystem::exists(dir)) << org;
  }
  for (int days : {0, -1, kMaxValidityDays + 1}) {
    KeysInitOptions options;
    options.validity_days = days;
    EXPECT_THROW(ValidateKeysInitOptions(options), std::invalid_argument) << days;
  }
  KeysInitOptions fine;
  fine.organisation = "Hospital Lab-2 v.1_a";
  fine.validity_days = kMaxValidityDays;
  EXPECT_NO_THROW(ValidateKeysInitOptions(fine));
  fine.organisation = std::string(kMaxOrganisationLength, 'a');
  EXPECT_NO_THROW(ValidateKeysInitOptions(fine));
}

}  // namespace
}  // namespace robossis::link
