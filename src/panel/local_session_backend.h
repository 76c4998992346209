#pragma once
// The panel's own session, for `robossis panel` without a remote follower: the runtime's follower unit
// (teleop::FollowerUnit: commands, set-point validation, the state machine, watchdog, guard, actuation) over a
// follower back end (teleop::MakeFollowerBackEnd: the Bullet RSR by default, or the LinuxCNC HAL drives of a real
// robot on this machine) through a teleop::InProcessLink, and on the link's leader
// side either the panel's jogs or, in haptic mode, the runtime's leader unit (teleop::LeaderUnit) with a haptic
// device (the simulated sigma.7 by default) and the chosen rendering method. Behind the same PanelBackend as the
// runtime's, so the panel and its scripted tests do not depend on which one runs.
//
// Nothing here decides a state or validates a pose: state commands go as StateCommandMessages through the link's
// operator queue, the state display is the follower unit's FollowerStatusMessage, a jog is played as 1 kHz
// set-points through the link's leader side by a JogPlayer (jog_player.h), and in haptic mode the leader unit sends
// its own set-points (the walls rendered, the set-point made feasible) exactly as in `robossis teleop`.
//
// Haptic mode: switching it on builds a leader unit (the rendering method, the speed caps of the request, starting
// at the follower's measured pose) on the panel thread and hands it to the leader-side loop through an SPSC queue;
// a new method or new caps (only while clutched, or with haptic mode off) build a new one the same way. The loop
// never allocates or frees: it hands a unit it no longer runs back through a second queue, and the panel thread
// frees it. Switching haptic mode off zeroes the device's force and resynchronises the jog player.
//
// Threads: the panel thread calls the PanelBackend methods (it is the operator queue's one producer). With Start(),
// two loops (rt::PeriodicLoop: absolute CLOCK_MONOTONIC deadlines, SCHED_FIFO where permitted, overruns counted):
// the follower unit at its tick rate (10 kHz) and the leader side at the link's 1 kHz (the jog player or the leader unit: the set-point channel's one
// producer and the status channel's one consumer). Without Start(), a test advances a SimulatedClock and calls
// Step(), which runs the leader side every tenth follower tick. They meet only through SPSC queues and seqlock
// snapshots. Step() and the leader-side tick allocate nothing, lock nothing and never throw.

#include <atomic>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "geometry/boundary_atlas.h"
#include "haptics/device/haptic_device.h"
#include "haptics/haptics_config.h"
#include "haptics/rendering/haptic_types.h"
#include "haptics/transfer/transfer_config.h"
#include "robot/actuation/actuation_config.h"
#include "robot/rsr_model.h"
#include "robot/sigma7_model.h"
#include "robot/follower.h"
#include "src/core/rt/clock.h"
#include "src/core/rt/periodic_loop.h"
#include "src/core/rt/snapshot.h"
#include "src/core/rt/spsc_queue.h"
#include "src/panel/jog_player.h"
#include "src/panel/panel_backend.h"
#include "src/teleop/follower_config.h"
#include "src/teleop/follower_unit.h"
#include "src/teleop/in_process_link.h"
#include "src/teleop/leader_config.h"
#include "src/teleop/leader_unit.h"

namespace robossis::panel {

// What the panel's haptic mode needs: the device and the leader unit's configs (as `robossis teleop` loads them,
// teleop::TeleopSetup). The caps in `transfer` are replaced by the ones the panel asks for.
struct HapticLeaderSetup {
  const robot::Sigma7Model* sigma7 = nullptr;  // must outlive the backend
  haptics::HapticsConfig haptics;
  transfer::TransferConfig transfer;
  teleop::LeaderConfig leader;
  std::string device = "sim";                  // haptics::MakeDevice spec
  std::shared_ptr<const geometry::BoundaryAtlas> atlas;  // the "mesh" method's (the others do without)
};

class LocalSessionBackend final : public PanelBackend {
 public:
  // `clock` is the shared clock of the link, the follower unit and the jog player: a MonotonicClock for the loop
  // thread, a SimulatedClock for a test that advances it and calls Step(). `back_end` is disabled here (the follower
  // unit starts DISABLED). The follower unit ticks at rates.actuation_rate_hz, the leader side (jog player or leader
  // unit) at rates.transfer_rate_hz, as in `robossis teleop`. Keeps references to model and clock.
  LocalSessionBackend(const robot::RsrModel& model, std::unique_ptr<robot::Follower> back_end,
                      const teleop::FollowerConfig& follower_config, const actuation::ActuationConfig& actuation_config,
                      const JogLimits& jog_limits, const transfer::TransferRates& rates, const rt::Clock& clock);
  ~LocalSessionBackend() override;

  // Gives the panel a haptic leader: opens the device (haptics::MakeDevice) and enables its forces. Call before
  // Start() or the first Step(). Without it, haptic mode is refused. Throws std::invalid_argument for an unknown
  // device, std::runtime_error when the device cannot be opened or refuses its forces.
  void AttachHapticLeader(HapticLeaderSetup setup);

  // The loop threads (the clock must be a rt::MonotonicClock: std::logic_error otherwise). Without them, a test
  // drives Step() itself. Returns what real-time setup was refused (SCHED_FIFO), for the caller to print.
  std::vector<std::string> Start();
  void Stop();
  // One follower tick at clock.NowS(): without the loop threads, every 1 ms first the leader side's tick (the jog
  // and haptic orders, then the jog player's set-point or the leader unit's tick); then FollowerUnit::Tick().
  // Real-time.
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
  // The newest haptic leader's latest tick (its LeaderUnit::latest() snapshot); false before haptic mode first ran.
  bool ReadLeaderRecord(teleop::LeaderTickRecord& record) noexcept;

 private:
  // One leader unit with its renderer and its settings (the panel thread owns it; the loop only runs it).
  struct HapticLeader {
    std::unique_ptr<haptics::HapticRenderer> renderer;
    std::unique_ptr<teleop::LeaderUnit> unit;
    int method = 0;
    double max_linear_speed_m_s = 0;
    double max_angular_speed_rad_s = 0;
  };
  struct Order {  // plain doubles: the queue copies it by value
    enum Kind : std::uint8_t { kJog, kStopJog, kHaptic } kind = kJog;
    double delta_p_F[3] = {0, 0, 0};    // m
    double delta_rot_F[3] = {0, 0, 0};  // rad
    double duration_s = 0;
    bool haptic = false;
    bool clutched = false;
    HapticLeader* leader = nullptr;      // a new leader unit to run (owned by the panel thread's list)
  };
  // The two loops' tasks.
  class FollowerTask final : public rt::PeriodicTask {
   public:
    explicit FollowerTask(LocalSessionBackend& backend) : backend_(backend) {}
    void Tick(std::int64_t) noexcept override { backend_.Step(); }

   private:
    LocalSessionBackend& backend_;
  };
  class LeaderTask final : public rt::PeriodicTask {
   public:
    explicit LeaderTask(LocalSessionBackend& backend) : backend_(backend) {}
    void Tick(std::int64_t) noexcept override { backend_.LeaderSideTick(); }

   private:
    LocalSessionBackend& backend_;
  };
  void LeaderSideTick() noexcept;
  void FollowerTick() noexcept;
  // Panel thread: builds a leader unit for the request, starting at X_FM_start. Throws on a bad method.
  std::unique_ptr<HapticLeader> BuildLeader(const HapticModeRequest& request, const Eigen::Isometry3d& X_FM_start);
  void FreeRetiredLeaders() noexcept;

  const robot::RsrModel& model_;
  const JogLimits jog_limits_;
  const double period_s_;           // the follower unit's tick
  const double setpoint_period_s_;  // the leader side's tick
  const int ticks_per_setpoint_;
  const rt::Clock& clock_;
  const teleop::FollowerConfig follower_config_;        // the follower unit keeps references to its arguments
  const actuation::ActuationConfig actuation_config_;
  std::unique_ptr<robot::Follower> back_end_;
  teleop::InProcessLink link_;
  std::unique_ptr<teleop::FollowerUnit> unit_;
  JogPlayer player_;

  // Haptic mode (the device is read and written by the leader side only).
  std::unique_ptr<HapticLeaderSetup> haptic_setup_;
  std::unique_ptr<haptics::HapticDevice> device_;
  std::uint64_t leader_session_base_ = 0;
  std::uint64_t leaders_built_ = 0;  // each leader unit is a new leader session: base + this count, never reused

  // Panel → loop.
  rt::SpscQueue<Order> orders_{64};
  std::uint64_t command_sequence_ = 0;  // panel thread
  // Panel-thread state: the leader units built so far (the newest is the one the loop runs or will run), and
  // haptic mode as last granted.
  std::deque<std::unique_ptr<HapticLeader>> leaders_;
  bool haptic_granted_ = false;
  // Loop → panel: leader units the loop will not run again.
  rt::SpscQueue<HapticLeader*> retired_{64};
  // Loop → panel.
  rt::Snapshot<LoopHealth> health_;
  struct CommandedPose {
    double p[3];
    double q[4];  // w, x, y, z
  };
  rt::Snapshot<CommandedPose> commanded_;

  // Leader-side state (the leader loop, or Step() without it).
  HapticLeader* active_leader_ = nullptr;
  bool haptic_active_ = false;
  std::atomic<double> last_presence_s_{-1};  // read by the follower side for the set-point age

  // Follower-side state.
  std::uint64_t tick_ = 0;
  double last_step_s_ = -1;
  LoopHealth health_record_;

  bool threaded_ = false;  // the leader side (and the back end's plant, if any) run on loops of their own
  FollowerTask follower_task_{*this};
  LeaderTask leader_task_{*this};
  robot::Follower::Plant plant_;  // the back end's robot, if it runs beside the controller (the simulation)
  std::int64_t next_plant_ns_ = 0;  // Step() without the loops: when the plant is next due
  std::unique_ptr<rt::PeriodicLoop> follower_loop_;
  std::unique_ptr<rt::PeriodicLoop> leader_loop_;
  std::unique_ptr<rt::PeriodicLoop> plant_loop_;
};

}  // namespace robossis::panel
