#pragma once
// The follower unit of Fig. 2: one 10 kHz actuation tick at a time. Each Tick() takes the queued state commands,
// takes the newest set-point and validates it (SetPointValidator: the one validated path), runs the safety state
// machine, follows the 1 kHz set-point at the tick by its twist (re-anchored after a clutch, a hold or a fault so
// that the robot does not jump), bounds the step to the speed and acceleration caps, passes it through the guard
// (no joint limit crossed, the spherical cones included; exact IK), runs the actuation (eq. 15–17), commands and
// services the back end, publishes the status (decimated) and pushes a per-tick record for the flight recorder.
//
// Not a loop: a runner calls Tick() on a thread at 10 kHz (real clock) or steps it (simulated clock). Tick() is
// allocation-free, lock-free and noexcept; the constructor allocates the record queue.
//
// E-stop: the first thing each tick reads is the link's E-stop count (FollowerLink::EStopsEngaged); when it has
// grown, the state machine E-stops (the drives are disabled in that tick), whatever the command queues hold.
//
// Motion: the commanded velocity changes by at most the acceleration caps per tick (SetPointLimits: the same caps
// the validator applies to the set-points) and never exceeds the speed caps; following approaches the wanted pose
// no faster than it can stop there.
// Watchdog: no valid set-point for hold_after_s -> the robot holds, decelerating from its commanded velocity to
// rest within the acceleration caps, and stopping at a joint limit rather than crossing it (the guard); counted in
// watchdog_holds. None for leader_lost_after_s -> the drives are disabled (reason kLeaderLost).
// Bilateral feedback: while following, the external wrench is estimated from the drive efforts and its power at the
// commanded twist booked into the port's energies (sent with the status). When the set-points carry the hand's
// energy (kSetPointEnergyBudget: the network form of the feedback's passivity), each step toward the set-point is
// shortened so that what the robot gives the environment stays within what the hand put in (follower_passivity.h);
// the step is taken from the commanded pose to the newest set-point, so motion held back is made up once the hand
// has paid for it.
// Recording: with a flight recorder watched (WatchRecorder), a recorder that failed, or a record the queue had no room
// for, holds the robot for good as the watchdog does (the set-points are ignored): no motion goes unrecorded.

#include <array>
#include <atomic>
#include <cstdint>

#include <Eigen/Geometry>

#include "robot/actuation/actuation_config.h"
#include "robot/actuation/actuator.h"
#include "robot/feasible_motion.h"
#include "robot/follower.h"
#include "src/core/rt/clock.h"
#include "src/core/rt/periodic_loop.h"
#include "src/core/rt/spsc_queue.h"
#include "src/teleop/follower_config.h"
#include "src/teleop/follower_passivity.h"
#include "src/teleop/follower_state_machine.h"
#include "src/teleop/link.h"
#include "src/teleop/setpoint_validator.h"

namespace robossis::teleop {

// One actuation tick, as the flight recorder stores it. Plain fixed-size record; SI; quaternions (w, x, y, z).
struct FollowerTickRecord {
  std::uint64_t tick = 0;
  double time_s = 0;
  // The newest valid set-point (as the leader sent it) and its sequence.
  std::uint64_t setpoint_sequence = 0;
  std::array<double, 3> setpoint_p_FM{};
  std::array<double, 4> setpoint_q_FM{1, 0, 0, 0};
  std::array<double, 6> setpoint_twist_F{};
  std::uint8_t setpoint_flags = 0;
  // The pose commanded this tick (after re-anchoring, the caps and the guard) and its twist.
  std::array<double, 3> cmd_p_FM{};
  std::array<double, 4> cmd_q_FM{1, 0, 0, 0};
  std::array<double, 6> cmd_twist_F{};
  std::array<double, 6> cmd_joints{};
  // What the back end measured after Service(), and when, on the back end's own clock (the simulation's physics
  // time, which advances in whole steps): speeds are differences over this time, not over the ticks.
  double meas_time_s = 0;
  std::array<double, 3> meas_p_FM{};
  std::array<double, 4> meas_q_FM{1, 0, 0, 0};
  std::array<double, 6> meas_joints{};
  std::array<double, 6> effort{};
  // The external wrench on the ring estimated from the efforts (zero while not following), and the follower port's
  // energies (feedback_passivity.h), as the status carries them.
  std::array<double, 6> wrench_F{};
  double port_energy_in_j = 0;
  double port_energy_out_j = 0;
  // The network form's follower half (follower_passivity.h): whether the newest set-point bounds the port (flag
  // kSetPointEnergyBudget while following), and the bound on port_energy_out_j it gives (the hand's input since
  // the bound started, divided by the gain, on the port's own scale).
  bool port_budgeted = false;
  double port_budget_j = 0;
  // The true external wrench of the measurement, where the back end knows it (a simulation, which applies the load
  // itself: robot::RsrFollowerState::true_wrench_F; hardware never does); what summary.json judges the shown load
  // against.
  bool true_load_known = false;
  std::array<double, 6> true_wrench_F{};
  double meas_min_margin = 0;  // the measured pose's tightest joint-limit margin (m or rad; < 0 violated)
  // Verdicts.
  OperatingState state = OperatingState::kDisabled;
  FaultReason reason = FaultReason::kNone;
  std::uint8_t back_end_fault = 0;   // robot::FollowerFault
  bool took_setpoint = false;        // a set-point arrived this tick ...
  SetPointVerdict setpoint_verdict = SetPointVerdict::kAccepted;  // ... and this was its verdict
  robot::FeasibleMotionStatus guard_status = robot::FeasibleMotionStatus::kTracked;
  std::uint8_t actuation_status = 0;  // actuation::ActuationStatus
  bool holding = false;               // not following (hold, clutch, ready, watchdog)
  bool meas_feasible = true;
  // Latency: the newest valid set-point's stamp (the leader clock at the device sample it came from), and the
  // clock when this tick's joint command went to the back end (after Command(); the tick's start when unpowered).
  std::int64_t setpoint_stamp_ns = 0;
  double command_time_s = 0;
};

struct FollowerCounters {
  std::uint64_t ticks = 0;
  std::uint64_t setpoints_taken = 0;
  std::uint64_t setpoints_accepted = 0;
  std::array<std::uint64_t, kNumSetPointVerdicts> setpoints_by_verdict{};  // index: SetPointVerdict
  std::uint64_t setpoints_rejected = 0;
  std::uint64_t watchdog_holds = 0;      // times the set-points stopped for hold_after_s while powered
  std::uint64_t leader_lost = 0;         // times the leader timeout disabled the drives
  std::uint64_t limit_violations = 0;    // ticks at which the measured joints broke a limit (cones included)
  std::uint64_t guard_constrained = 0;   // ticks at which the guard changed the wanted step
  std::uint64_t estops = 0;             // ticks at which the link's E-stop count had grown (each E-stops)
  std::uint64_t commands_taken = 0;
  std::uint64_t commands_refused = 0;
  std::uint64_t status_published = 0;
  std::uint64_t records_dropped = 0;     // the flight recorder's queue was full
};

class FollowerUnit final : public rt::PeriodicTask {
 public:
  // The start pose is the back end's measured pose (it must be inside the joint limits). Throws
  // std::invalid_argument on a bad config or an infeasible start. Keeps references to every argument.
  FollowerUnit(const robot::RsrModel& model, const actuation::ActuationConfig& actuation,
               const FollowerConfig& config, robot::Follower& back_end, FollowerLink& link, const rt::Clock& clock);

  // One actuation tick at clock.NowS().
  void Tick() noexcept;
  // As a loop's task: the unit reads its clock itself, the loop's tick time is not used.
  void Tick(std::int64_t) noexcept override { Tick(); }

  // The flight recorder's end of the record queue (one consumer thread).
  bool TakeRecord(FollowerTickRecord& record) noexcept { return records_.TryPop(record); }
  // The recorder's failure flag (set by the recorder on a write error, by this unit when its queue is full): once
  // set, the unit holds. Call before the loop starts; the flag must outlive the ticks. Null: no recorder watched.
  void WatchRecorder(std::atomic<bool>* failed) noexcept { recorder_failed_ = failed; }

  OperatingState state() const noexcept { return machine_.state(); }
  FaultReason reason() const noexcept { return machine_.reason(); }
  const FollowerCounters& counters() const noexcept { return counters_; }
  const Eigen::Isometry3d& commanded_pose() const noexcept { return X_cmd_; }
  const FollowerConfig& config() const noexcept { return config_; }

 private:
  Eigen::Isometry3d WantedPose(double now_s) noexcept;
  void PublishStatus(double now_s, const robot::RsrFollowerState& measured) noexcept;
  // The external wrench while following (else none), computed when the back end's measurement changes, and the
  // port's energy over dt at the commanded twist, every tick.
  void ObserveWrench(const robot::RsrFollowerState& measured, double dt) noexcept;
  // The share of `step` the network form's bound lets the robot take (1 unless the set-points carry the hand's
  // energy while following).
  double BudgetedStepShare(const Vector6d& step) noexcept;

  const robot::RsrModel& model_;
  FollowerConfig config_;
  robot::Follower& back_end_;
  FollowerLink& link_;
  const rt::Clock& clock_;
  SetPointValidator validator_;
  robot::FeasibleMotionGuard guard_;
  actuation::Actuator actuator_;
  FollowerStateMachine machine_;
  rt::SpscQueue<FollowerTickRecord> records_;
  std::atomic<bool>* recorder_failed_ = nullptr;
  FollowerLimits limits_;  // LimitsOf(config_): published with every status
  FollowerCounters counters_;
  FollowerTickRecord record_;
  std::uint64_t estops_seen_ = 0;  // the link's E-stop count at the last tick (0: one engaged before start acts)

  // Set-point state.
  bool has_setpoint_ = false;
  SetPointSample setpoint_;
  double setpoint_arrival_s_ = 0;
  std::uint64_t setpoint_sequence_ = 0;
  std::uint64_t setpoint_session_ = 0;  // the leader session of the newest valid set-point
  std::int64_t setpoint_stamp_ns_ = 0;
  std::uint8_t setpoint_flags_ = 0;
  bool setpoint_live_ = false;  // a valid set-point within hold_after_s (for the watchdog's edge)
  // Re-anchoring: the set-point and the commanded pose when following resumed.
  bool need_anchor_ = true;
  Eigen::Isometry3d X_anchor_setpoint_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d X_anchor_cmd_ = Eigen::Isometry3d::Identity();
  // Commanded motion.
  Eigen::Isometry3d X_cmd_ = Eigen::Isometry3d::Identity();
  Vector6d twist_cmd_ = Vector6d::Zero();
  double last_tick_s_ = 0;
  bool first_tick_ = true;
  double next_status_s_ = 0;
  std::uint64_t status_sequence_ = 0;
  // The external wrench (zero while not following) and the port's energies since the start.
  Vector6d wrench_F_ = Vector6d::Zero();
  WrenchSource wrench_source_ = WrenchSource::kNone;  // kNone: no estimate held (the next one is computed)
  double wrench_meas_time_s_ = 0;  // the measurement the estimate was computed from (RsrFollowerState::time_s)
  FollowerPassivity port_;
  // The network form's bound: the newest set-point's hand energy, and while the bound runs the offset that puts the
  // hand's input since it started on the port's out_j scale (restarted when following or the leader session starts).
  double setpoint_hand_energy_j_ = 0;
  bool budget_running_ = false;
  std::uint64_t budget_session_ = 0;
  double budget_offset_j_ = 0;
};

}  // namespace robossis::teleop
