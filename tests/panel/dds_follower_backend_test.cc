// The panel as a DDS link participant: in this process, a follower unit over the Bullet RSR behind a
// DdsFollowerLink on its own 10 kHz loop (secured with test credentials on loopback, as tests/link does), and the
// panel's DdsFollowerBackend with the panel's credentials: the panel sees the remote state and pose, and its state
// commands (Home, E-stop, Reset) go through the follower unit's one command path; jogs and haptic mode are refused.

#include <gtest/gtest.h>

#include <memory>

#include "haptics/transfer/transfer_config.h"
#include "robot/actuation/actuation_config.h"
#include "robot/sim/rsr_simulation.h"
#include "robot/sim/sim_config.h"
#include "src/core/config.h"
#include "src/core/rt/clock.h"
#include "src/core/rt/periodic_loop.h"
#include "src/link/dds_follower_link.h"
#include "src/panel/dds_follower_backend.h"
#include "src/panel/view_model.h"
#include "src/teleop/follower_config.h"
#include "src/teleop/follower_unit.h"
#include "tests/link/link_test_support.h"

namespace robossis::panel {
namespace {

using link::testing::LoopbackOptions;
using link::testing::WaitFor;
using teleop::OperatingState;
using teleop::StateCommand;

// The remote follower: everything `robossis follower` runs, in this process.
struct RemoteFollower {
  RemoteFollower()
      : model(robot::RsrModel::FromYaml(DefaultDataDir() / "config" / "rsr.yaml")),
        transfer(transfer::TransferConfig::FromYaml(DefaultDataDir() / "config" / "transfer.yaml")),
        follower(teleop::FollowerConfig::FromYaml(DefaultDataDir() / "config" / "follower.yaml", transfer.caps)),
        actuation(actuation::ActuationConfig::FromYaml(DefaultDataDir() / "config" / "actuation.yaml")),
        sim_config(sim::LoadSimConfig(DefaultDataDir() / "config" / "sim.yaml", DefaultDataDir())),
        link(LoopbackOptions(link::Role::kFollower), clock) {
    sim::SimOptions options;
    options.with_bone = false;
    options.with_traction = false;
    back_end = std::make_unique<sim::RsrSimulation>(model, sim_config, nullptr, nullptr, model.geometry().X_FM_home,
                                                    options);
    back_end->Disable();
    unit = std::make_unique<teleop::FollowerUnit>(model, actuation, follower, *back_end, link, clock);
    rt::LoopOptions loop;
    loop.name = "follower";
    loop.period_ns = 100'000;  // 10 kHz
    loop.try_realtime = false;
    runner = std::make_unique<rt::PeriodicLoop>(clock, *unit, loop);
    runner->Start(static_cast<std::int64_t>(clock.NowS() * 1e9) + loop.period_ns);  // ns on the clock
  }
  ~RemoteFollower() { runner->Stop(); }

  rt::MonotonicClock clock;
  robot::RsrModel model;
  transfer::TransferConfig transfer;
  teleop::FollowerConfig follower;
  actuation::ActuationConfig actuation;
  sim::SimConfig sim_config;
  link::DdsFollowerLink link;
  std::unique_ptr<sim::RsrSimulation> back_end;
  std::unique_ptr<teleop::FollowerUnit> unit;
  std::unique_ptr<rt::PeriodicLoop> runner;
};

bool WaitForState(DdsFollowerBackend& panel, OperatingState state) {
  return WaitFor([&] {
    teleop::FollowerStatusMessage status;
    return panel.ReadStatus(status) && status.state == state;
  });
}

TEST(DdsFollowerBackend, ThePanelWatchesARemoteFollowerAndCommandsItsStates) {
  RemoteFollower remote;
  DdsFollowerBackend panel(LoopbackOptions(link::Role::kPanel));
  ASSERT_TRUE(WaitForState(panel, OperatingState::kDisabled));
  teleop::FollowerStatusMessage status;
  ASSERT_TRUE(panel.ReadStatus(status));
  const PanelViewModel view = BuildViewModel(remote.model, status);
  EXPECT_NEAR(view.pose_mm_deg[2], 1e3 * remote.model.geometry().X_FM_home.translation().z(), 0.5);
  LoopHealth health;
  ASSERT_TRUE(panel.ReadHealth(health));
  EXPECT_GE(health.setpoint_age_s, 0);

  ASSERT_TRUE(panel.SendCommand(StateCommand::kHome));
  ASSERT_TRUE(panel.SendCommand(StateCommand::kEnable));
  EXPECT_TRUE(WaitForState(panel, OperatingState::kReady));
  ASSERT_TRUE(panel.SendCommand(StateCommand::kEStop));
  EXPECT_TRUE(WaitForState(panel, OperatingState::kEStop));
  ASSERT_TRUE(panel.ReadStatus(status));
  EXPECT_EQ(status.fault_reason, teleop::FaultReason::kEStop);
  ASSERT_TRUE(panel.SendCommand(StateCommand::kReset));
  EXPECT_TRUE(WaitForState(panel, OperatingState::kDisabled));
  remote.runner->Stop();
  EXPECT_EQ(remote.unit->counters().commands_refused, 0u);
  EXPECT_GE(remote.unit->counters().commands_taken, 3u);  // home, enable, reset (the E-stop is not a queued command)
  EXPECT_EQ(remote.unit->counters().estops, 1u);
}

TEST(DdsFollowerBackend, JogsAndHapticModeAreRefusedWithTheReason) {
  RemoteFollower remote;
  DdsFollowerBackend panel(LoopbackOptions(link::Role::kPanel));
  JogRequest request;
  request.axis = JogAxis::kZ;
  request.amount = 0.001;
  const JogVerdict verdict = panel.StartJog(request);
  EXPECT_FALSE(verdict.accepted);
  EXPECT_NE(verdict.reason.find("set-points"), std::string::npos) << verdict.reason;
  HapticModeRequest haptic;
  haptic.enabled = true;
  std::string reason;
  EXPECT_FALSE(panel.RequestHapticMode(haptic, reason));
  EXPECT_NE(reason.find("set-points"), std::string::npos) << reason;
  Eigen::Isometry3d X;
  EXPECT_FALSE(panel.ReadCommandedPose(X));
}

}  // namespace
}  // namespace robossis::panel
