#pragma once
// The panel's own follower, for `robossis panel` without a teleoperation runtime: the runtime's follower unit
// (teleop::FollowerUnit: commands, set-point validation, the state machine, watchdog, guard, actuation) over the
// Bullet RSR (sim::RsrSimulation, without the fragments) through a teleop::InProcessLink, behind the same
// PanelBackend as the runtime's, so the panel and its scripted tests do not depend on which one runs.
//
// Nothing here decides a state or validates a pose: state commands go as StateCommandMessages through the link's
// operator queue, the state display is the follower unit's FollowerStatusMessage, and a jog is played as 1 kHz
// set-points through the link's leader side by a JogPlayer (jog_player.h), exactly as a leader would send them.
//
// Threads: the panel thread calls the PanelBackend methods (it is the operator queue's one producer); the loop
// thread (Start) runs Step() at the follower's tick rate on absolute CLOCK_MONOTONIC deadlines and counts overruns.
// They meet only through SPSC queues (jog and haptic orders) and seqlock snapshots (status, health, commanded pose).
// Step() allocates nothing, locks nothing and never throws.

#include <atomic>
#include <memory>
#include <thread>

#include "robot/actuation/actuation_config.h"
#include "robot/rsr_model.h"
#include "robot/sim/rsr_simulation.h"
#include "robot/sim/sim_config.h"
#include "src/core/rt/clock.h"
#include "src/core/rt/snapshot.h"
#include "src/core/rt/spsc_queue.h"
#include "src/panel/jog_player.h"
#include "src/panel/panel_backend.h"
#include "src/teleop/follower_config.h"
#include "src/teleop/follower_unit.h"
#include "src/teleop/in_process_link.h"

namespace robossis::panel {

class SimulatedFollowerBackend final : public PanelBackend {
 public:
  // `clock` is the shared clock of the link, the follower unit and the jog player: a MonotonicClock for the loop
  // thread, a SimulatedClock for a test that advances it and calls Step(). Keeps references to model and clock.
  SimulatedFollowerBackend(const robot::RsrModel& model, const sim::SimConfig& sim_config, bool gravity,
                           const teleop::FollowerConfig& follower_config,
                           const actuation::ActuationConfig& actuation_config, const JogLimits& jog_limits,
                           double tick_rate_hz, const rt::Clock& clock);
  ~SimulatedFollowerBackend() override;

  // The loop thread (the clock must be CLOCK_MONOTONIC's). Without it, a test drives Step() itself.
  void Start();
  void Stop();
  // One follower tick at clock.NowS(): the jog and haptic orders, every 1 ms the leader side's set-point, then
  // FollowerUnit::Tick(). Real-time.
  void Step() noexcept;

  bool ReadStatus(teleop::FollowerStatusMessage& status) noexcept override { return link_.ReadFollowerStatus(status); }
  bool ReadHealth(LoopHealth& health) noexcept override { return health_.Read(health); }
  bool ReadHandWrench(HandWrench& wrench) noexcept override;
  bool ReadCommandedPose(Eigen::Isometry3d& X_FM) noexcept override;
  bool SendCommand(teleop::StateCommand command) noexcept override;
  JogVerdict PreviewJog(const JogRequest& request) override;
  JogVerdict StartJog(const JogRequest& request) override;
  void StopJog() noexcept override;
  bool RequestHapticMode(const HapticModeRequest& request, std::string& reason) override;

  // The follower unit's counters (loop thread; for tests after the loop stopped).
  const teleop::FollowerCounters& follower_counters() const noexcept { return unit_->counters(); }

 private:
  struct Order {  // plain doubles: the queue copies it by value
    enum Kind : std::uint8_t { kJog, kStopJog, kHaptic } kind = kJog;
    double delta_p_F[3] = {0, 0, 0};    // m
    double delta_rot_F[3] = {0, 0, 0};  // rad
    double duration_s = 0;
    bool haptic = false;
    bool clutched = false;
  };
  void Loop();

  const robot::RsrModel& model_;
  const JogLimits jog_limits_;
  const double period_s_;
  const int ticks_per_setpoint_;
  const rt::Clock& clock_;
  const teleop::FollowerConfig follower_config_;        // the follower unit keeps references to its arguments
  const actuation::ActuationConfig actuation_config_;
  std::unique_ptr<sim::RsrSimulation> sim_;
  teleop::InProcessLink link_;
  std::unique_ptr<teleop::FollowerUnit> unit_;
  JogPlayer player_;

  // Panel → loop.
  rt::SpscQueue<Order> orders_{64};
  std::uint64_t command_sequence_ = 0;  // panel thread
  // Loop → panel.
  rt::Snapshot<LoopHealth> health_;
  struct CommandedPose {
    double p[3];
    double q[4];  // w, x, y, z
  };
  rt::Snapshot<CommandedPose> commanded_;

  // Loop-thread state.
  std::uint64_t tick_ = 0;
  double last_step_s_ = -1;
  LoopHealth health_record_;

  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace robossis::panel
