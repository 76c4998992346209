#include "src/teleop/in_process_link.h"

#include <gtest/gtest.h>

#include "src/teleop/local_command_link.h"

namespace robossis::teleop {
namespace {

TEST(InProcessLinkTest, SetPointsAreLatestValueWithArrivalTime) {
  rt::SimulatedClock clock;
  InProcessLink link(clock);
  SetPointMessage m;
  std::int64_t arrival = 0;
  EXPECT_FALSE(link.TakeSetPoint(m, arrival));
  m.sequence = 1;
  clock.SetNs(1000);
  link.SendSetPoint(m);
  m.sequence = 2;
  clock.SetNs(2000);
  link.SendSetPoint(m);
  SetPointMessage got;
  ASSERT_TRUE(link.TakeSetPoint(got, arrival));
  EXPECT_EQ(got.sequence, 2u);  // the newer replaced the unread older one
  EXPECT_EQ(arrival, 2000);
  EXPECT_FALSE(link.TakeSetPoint(got, arrival));  // taken once
}

TEST(InProcessLinkTest, CommandsFromBothProducersAreQueuedAndNeverLost) {
  rt::SimulatedClock clock;
  InProcessLink link(clock, 8);
  StateCommandMessage c;
  c.command = StateCommand::kEnable;
  ASSERT_TRUE(link.operator_commands().Send(c));
  c.command = StateCommand::kDisable;
  ASSERT_TRUE(link.SendCommand(c));
  StateCommandMessage got;
  ASSERT_TRUE(link.TakeCommand(got));
  EXPECT_EQ(got.command, StateCommand::kDisable);  // the leader's queue first
  ASSERT_TRUE(link.TakeCommand(got));
  EXPECT_EQ(got.command, StateCommand::kEnable);
  EXPECT_FALSE(link.TakeCommand(got));
  for (int i = 0; i < 8; ++i) ASSERT_TRUE(link.SendCommand(c));
  EXPECT_FALSE(link.SendCommand(c));  // full: refused and counted
  EXPECT_EQ(link.commands_dropped(), 1u);
  // The E-stop, from either producer, as a method or as the old command, is never queued and never refused.
  EXPECT_EQ(link.EStopsEngaged(), 0u);
  c.command = StateCommand::kEStop;
  EXPECT_TRUE(link.SendCommand(c));
  EXPECT_TRUE(link.operator_commands().Send(c));
  link.SendEStop();
  link.operator_commands().SendEStop();
  EXPECT_EQ(link.EStopsEngaged(), 4u);
  EXPECT_EQ(link.commands_dropped(), 1u);
}

TEST(LocalCommandLinkTest, ALocalEStopIsNeverQueuedAndAddsToTheLinks) {
  rt::SimulatedClock clock;
  InProcessLink link(clock);
  LocalCommandLink local(link, 2);
  StateCommandMessage c;
  c.command = StateCommand::kEnable;
  ASSERT_TRUE(local.SendLocal(c));
  ASSERT_TRUE(local.SendLocal(c));
  EXPECT_FALSE(local.SendLocal(c));  // the local queue is full
  c.command = StateCommand::kEStop;
  EXPECT_TRUE(local.SendLocal(c));  // the E-stop is not queued: never refused
  link.SendEStop();                 // and the network's add to it
  EXPECT_EQ(local.EStopsEngaged(), 2u);
  EXPECT_EQ(local.local_commands_dropped(), 1u);
}

TEST(InProcessLinkTest, StatusIsTakenOnceAndReadableByWatchers) {
  rt::SimulatedClock clock;
  InProcessLink link(clock);
  FollowerStatusMessage s;
  s.sequence = 3;
  link.PublishStatus(s);
  FollowerStatusMessage got;
  ASSERT_TRUE(link.TakeFollowerStatus(got));
  EXPECT_EQ(got.sequence, 3u);
  EXPECT_FALSE(link.TakeFollowerStatus(got));
  EXPECT_TRUE(link.ReadFollowerStatus(got));
}

}  // namespace
}  // namespace robossis::teleop
