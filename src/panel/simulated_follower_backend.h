#pragma once
// The panel's own simulated follower, for `robossis panel` without a teleoperation runtime: the Bullet RSR
// (robot/sim/rsr_simulation.h) on a loop thread with the follower's state machine, executing the panel's jogs as
// eq. 9 timed moves. It stands in for the follower unit of the teleoperation runtime, behind the same
// PanelBackend, so the panel and its scripted tests do not depend on which one runs.
//
// State machine (StateCommand → OperatingState):
//   DISABLED --home--> HOMING --(homed)--> READY --enable / haptic on--> ENABLED <--clutch--> CLUTCHED
//   any --disable--> DISABLED (unless latched);  any --e-stop--> ESTOP (latched);  a back-end fault → FAULT (latched)
//   ESTOP / FAULT --reset--> READY (drives re-enabled, holding where they are)
// Jogs run only in READY (ENABLED belongs to the leader's set-points); E-stop, disable and Stop end a jog where it is.
//
// Threads: the panel thread calls the PanelBackend methods; the loop thread (Start) runs Step() at the loop rate on
// absolute deadlines and counts overruns. They meet only through SPSC queues (commands, jogs, haptic requests) and
// seqlock snapshots (status, health). Step() allocates nothing, locks nothing and never throws.

#include <atomic>
#include <memory>
#include <optional>
#include <thread>

#include "haptics/transfer/timed_move.h"
#include "robot/rsr_model.h"
#include "robot/sim/rsr_simulation.h"
#include "robot/sim/sim_config.h"
#include "src/core/rt/snapshot.h"
#include "src/core/rt/spsc_queue.h"
#include "src/panel/panel_backend.h"
#include "src/teleop/setpoint_validator.h"

namespace robossis::panel {

class SimulatedFollowerBackend final : public PanelBackend {
 public:
  SimulatedFollowerBackend(const robot::RsrModel& model, const sim::SimConfig& sim_config, bool gravity,
                           const JogLimits& jog_limits, double loop_rate_hz);
  ~SimulatedFollowerBackend() override;

  // The loop thread on CLOCK_MONOTONIC. Without it, a test drives Step() itself in simulated time.
  void Start();
  void Stop();
  // One loop tick at runtime time now_s (s): commands, the jog's eq. 9 set-point, the physics, the status. Real-time.
  void Step(double now_s) noexcept;

  bool ReadStatus(teleop::FollowerStatusMessage& status) noexcept override { return status_.Read(status); }
  bool ReadHealth(LoopHealth& health) noexcept override { return health_.Read(health); }
  bool ReadHandWrench(HandWrench& wrench) noexcept override;
  bool ReadCommandedPose(Eigen::Isometry3d& X_FM) noexcept override;
  bool SendCommand(teleop::StateCommand command) noexcept override;
  JogVerdict PreviewJog(const JogRequest& request) override;
  JogVerdict StartJog(const JogRequest& request) override;
  void StopJog() noexcept override;
  bool RequestHapticMode(const HapticModeRequest& request, std::string& reason) override;

 private:
  struct JogOrder {  // plain doubles: the queue copies it by value
    bool stop = false;
    double delta_p_F[3] = {0, 0, 0};    // m
    double delta_rot_F[3] = {0, 0, 0};  // rad
    double duration_s = 0;
  };
  void ApplyCommand(teleop::StateCommand command) noexcept;
  void ApplyJogOrder(const JogOrder& order, double now_s) noexcept;
  void ApplyHapticRequest(const HapticModeRequest& request) noexcept;
  void Latch(teleop::OperatingState state, teleop::FaultReason reason) noexcept;
  void CommandPose(const Eigen::Isometry3d& X_FM, const Vector6d& twist, double now_s) noexcept;
  void Publish(double now_s) noexcept;
  void Loop();

  const robot::RsrModel model_;
  const JogLimits jog_limits_;
  const double period_s_;
  std::unique_ptr<sim::RsrSimulation> sim_;
  teleop::SetPointValidator validator_;  // loop thread: every commanded pose goes through it

  // Panel → loop.
  rt::SpscQueue<teleop::StateCommandMessage> commands_{64};
  rt::SpscQueue<JogOrder> jogs_{16};
  rt::SpscQueue<HapticModeRequest> haptic_{16};
  std::uint64_t command_sequence_ = 0;  // panel thread
  // Loop → panel.
  rt::Snapshot<teleop::FollowerStatusMessage> status_;
  rt::Snapshot<LoopHealth> health_;
  struct CommandedPose {
    double p[3];
    double q[4];  // w, x, y, z
  };
  rt::Snapshot<CommandedPose> commanded_;

  // Loop-thread state.
  teleop::OperatingState state_ = teleop::OperatingState::kDisabled;
  teleop::FaultReason fault_ = teleop::FaultReason::kNone;
  std::uint8_t back_end_fault_ = 0;
  Eigen::Isometry3d X_hold_ = Eigen::Isometry3d::Identity();
  std::optional<transfer::TimedMove> move_;
  double last_setpoint_s_ = -1;
  double last_step_s_ = -1;
  std::uint64_t sequence_ = 0;
  std::uint64_t setpoints_accepted_ = 0;
  std::uint64_t setpoints_rejected_ = 0;
  LoopHealth health_record_;

  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace robossis::panel
