// The E-stop over DDS: its own topic (rt/<ns>/estop), read by the follower link's receive thread into an atomic
// count that the follower unit reads first every tick. A flood of commands fills the follower's command queue (drops
// counted), then an E-stop arrives; the drives must be off after the first 10 kHz tick following its arrival
// (a simulated clock and the pulse recorder as the back end: ticks are counted, not wall time). The waits only
// poll for what must happen (no timing assertions).

#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "robot/actuation/pulse_recorder_follower.h"
#include "src/core/rt/clock.h"
#include "src/link/dds_follower_link.h"
#include "src/link/dds_leader_link.h"
#include "src/link/estop_sender.h"
#include "src/teleop/follower_unit.h"
#include "tests/link/link_test_support.h"
#include "tests/teleop/follower_fixture.h"

namespace robossis::link {
namespace {

using testing::LoopbackOptions;
using testing::WaitFor;

constexpr std::int64_t kTickNs = 100'000;  // 10 kHz

enum class Sender { kLeaderEStop, kPanelEStopCommand, kOtherPanelEStop };

struct EStopCase {
  Sender sender;
  bool insecure;
};

class LinkEStopTest : public ::testing::TestWithParam<EStopCase>, protected teleop::ShippedFollowerSetup {
 protected:
  const teleop::FollowerConfig config_ = ShippedFollowerConfig();
  rt::SimulatedClock clock_;
  actuation::PulseRecorderFollower back_end_{model_, actuation_, home_, 1 << 16, 1 << 16};
  std::uint64_t sequence_ = 0;

  // The panel's next command (its session, a new sequence and stamp: never a replay).
  teleop::StateCommandMessage Command(teleop::StateCommand c) {
    teleop::StateCommandMessage m;
    m.command = c;
    m.source = teleop::kFromPanel;
    m.session = 7;
    m.sequence = ++sequence_;
    m.stamp_ns = static_cast<std::int64_t>(sequence_);
    return m;
  }
};

std::string CaseName(const ::testing::TestParamInfo<EStopCase>& info) {
  static const char* const kNames[] = {"LeaderEStop", "PanelEStopCommand", "OtherPanelEStop"};
  return std::string(kNames[static_cast<int>(info.param.sender)]) + (info.param.insecure ? "Unsecured" : "Secured");
}

TEST_P(LinkEStopTest, AnEStopBehindAFloodOfCommandsDisablesTheDrivesInOneTick) {
  const bool insecure = GetParam().insecure;
  DdsFollowerLink follower(LoopbackOptions(Role::kFollower, insecure), clock_);
  DdsLeaderLink leader(LoopbackOptions(Role::kLeader, insecure));
  DdsLeaderLink panel(LoopbackOptions(Role::kPanel, insecure));  // the one participant that commands
  teleop::FollowerUnit unit(model_, actuation_, config_, back_end_, follower, clock_);
  const auto tick = [&] {
    clock_.AdvanceNs(kTickNs);
    unit.Tick();
  };
  // The panel enables the follower once both ends have found it (commands are volatile: one sent before the match
  // is lost, so the enable is repeated until it took).
  ASSERT_TRUE(WaitFor([&] {
    tick();
    return panel.Statistics().state_received > 0 && leader.Statistics().followers_matched > 0;
  }));
  ASSERT_TRUE(WaitFor([&] {
    panel.SendCommand(Command(teleop::StateCommand::kEnable));
    tick();
    return unit.state() == teleop::OperatingState::kReady;
  }));
  ASSERT_TRUE(back_end_.State().enabled);

  // Commands while the unit does not tick, until the follower's queue overflows. (Whether the panel's own queue
  // fills first depends on the scheduler: its send thread runs at real-time priority where allowed and may drain it
  // as fast as it is filled. The E-stop does not pass through that queue.)
  for (int i = 0; i < 10000; ++i) panel.SendCommand(Command(teleop::StateCommand::kEnable));
  ASSERT_TRUE(WaitFor([&] {
    panel.SendCommand(Command(teleop::StateCommand::kEnable));  // more, until the follower's queue overflows
    return follower.Statistics().commands_dropped > 0;
  }));

  std::unique_ptr<DdsLeaderLink> other_panel;
  switch (GetParam().sender) {
    case Sender::kLeaderEStop: leader.SendEStop(); break;
    case Sender::kPanelEStopCommand: EXPECT_TRUE(panel.SendCommand(Command(teleop::StateCommand::kEStop))); break;
    case Sender::kOtherPanelEStop:
      // Another participant, joining now: its sample reaches the follower whatever the panel's queue holds.
      other_panel = std::make_unique<DdsLeaderLink>(LoopbackOptions(Role::kPanel, insecure));
      other_panel->SendEStop();
      break;
  }
  ASSERT_TRUE(WaitFor([&] { return follower.EStopsEngaged() > 0; }));  // arrived (the unit has not ticked since)
  int ticks = 0;
  while (back_end_.State().enabled && ticks < 1000) {
    tick();
    ++ticks;
  }
  EXPECT_EQ(ticks, 1);
  EXPECT_EQ(unit.state(), teleop::OperatingState::kEStop);
  EXPECT_EQ(unit.reason(), teleop::FaultReason::kEStop);
}

INSTANTIATE_TEST_SUITE_P(Senders, LinkEStopTest,
                         ::testing::Values(EStopCase{Sender::kLeaderEStop, true},
                                           EStopCase{Sender::kPanelEStopCommand, true},
                                           EStopCase{Sender::kOtherPanelEStop, true},
                                           EStopCase{Sender::kLeaderEStop, false},
                                           EStopCase{Sender::kPanelEStopCommand, false}),
                         CaseName);

TEST(LinkEStopLateJoinerTest, AFollowerThatJoinsAfterTheEStopStillLearnsOfIt) {
  // Transient-local: the sender's newest E-stop sample waits for a follower that was not there.
  rt::SimulatedClock clock;
  DdsLeaderLink leader(LoopbackOptions(Role::kLeader, true));
  leader.SendEStop();
  ASSERT_TRUE(WaitFor([&] { return leader.Statistics().estops_sent > 0; }));
  DdsFollowerLink follower(LoopbackOptions(Role::kFollower, true), clock);
  EXPECT_TRUE(WaitFor([&] { return follower.EStopsEngaged() == 1; }));
}

TEST(LinkEStopSenderTest, TheCommandLinesEStopIsConfirmedByTheFollowersState) {
  teleop::ShippedFollowerSetup setup;
  const teleop::FollowerConfig config = setup.ShippedFollowerConfig();
  rt::SimulatedClock clock;
  actuation::PulseRecorderFollower back_end(setup.model_, setup.actuation_, setup.home_, 1 << 16, 1 << 16);
  DdsFollowerLink follower(LoopbackOptions(Role::kFollower, true), clock);
  teleop::FollowerUnit unit(setup.model_, setup.actuation_, config, back_end, follower, clock);
  // The follower ticks on its own thread (its clock simulated), started and always stopped here.
  std::atomic<bool> stop{false};
  std::thread ticker([&] {
    while (!stop.load()) {
      clock.AdvanceNs(kTickNs);
      unit.Tick();
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  });
  const EStopSendResult r = SendEStopAndConfirm(LoopbackOptions(Role::kPanel, true), 10.0);
  stop.store(true);
  ticker.join();
  EXPECT_TRUE(r.follower_heard);
  EXPECT_TRUE(r.confirmed);
  EXPECT_EQ(unit.state(), teleop::OperatingState::kEStop);
}

}  // namespace
}  // namespace robossis::link
