#pragma once
// The leader unit of Fig. 2: the haptic side of the teleoperation, one Tick() per haptic period on its own loop.
//
// Each tick:
//   device read → (every transfer period) the hand sample into the motion transfer (eq. 10–12: the one HC→RSR
//   mapping, with the clutch, the eq. 11 scaling and the re-anchoring after a clutch) → the walls rendered at the
//   pose that transfer produced, i.e. at the pose the follower will be sent → device write;
//   (every transfer period) the set-point made feasible → LeaderLink::SendSetPoint.
//
// The set-point sent is always feasible, checked with the exact IK: where the hand pushes through a wall it stops
// at the boundary, at the proxy's pose for the proxy methods (the god-object is always feasible), else where the
// feasible-motion guard (robot/feasible_motion.h: a constrained least-squares step with every limit linearised)
// takes it from the last set-point toward the pose the transfer asks for. Every pose is judged as the follower
// receives it (position + quaternion); a pose that still fails the IK is never sent: the last one is repeated.
// The set-points then move toward that pose within the follower's speed and acceleration caps (capped_motion.h,
// the follower's own implementation), slow enough to stop there: a wall stops the set-point as smoothly as the
// follower may move, and its validator accepts every set-point. The twist sent is the set-point's own motion.
//
// The robot's own state gates it too: while the follower is not following (not enabled, or its status is older
// than follower_status_timeout_s), no force is displayed, the hand moves nothing, and the set-point, the walls and
// the motion transfer stay at the robot's measured pose (FollowerStatusMessage), so that the walls follow the real
// robot and following resumes from where it is.
//
// Operator presence (the device's button) gates everything: without it the clutch is open (the transfer ignores
// the hand, the follower is asked to hold) and no force is displayed; with it back, the mapping re-anchors, so
// nothing jumps. A device failure (failed, non-finite or stale read) zeroes the force (HapticDevice does) and
// latches the leader's fault and engages the E-stop (LeaderLink::SendEStop, once per failure): set-points carry
// kSetPointDeviceFault and no presence until RequestReset(); the follower leaves its E-stop by its own reset.
// The end of a replay is not a failure: the leader holds.
//
// Bilateral feedback (config.feedback.mode kBilateral): the follower's external wrench, as its newest status carries
// it, is mapped into the device frame by the transfer's frame map inverted as energy requires (f_O = s·R_FOᵀ·f_F,
// with s the motion scale: the hand's power is the ring's), scaled by the feedback gain, added to the walls within
// the caps, and passed through the passivity observer and controller of the feedback port (feedback_passivity.h).
// It is zero unless the follower follows (enabled, not clutched, not holding: its status says where its wrench came
// from) on a fresh status while this leader tracks.
// With config.feedback.detect_let_go the let-go detector (let_go_detector.h) judges every tick the load is shown by
// the force written at the last tick and the velocity it produced; once it believes the operator let go, the load is
// replaced by a damper (rest_damping_n_s_per_m) that brings the device to rest, until the presence or the clutch is
// taken anew (the leader stops tracking).
//
// Real time: Tick() allocates nothing, locks nothing, prints and throws nothing. Records go to the flight recorder
// through an SpscQueue (a full queue drops and counts), the latest one to a Snapshot for watchers.

#include <array>
#include <atomic>
#include <cstdint>

#include <Eigen/Geometry>

#include "haptics/device/haptic_device.h"
#include "haptics/rendering/haptic_types.h"
#include "haptics/transfer/motion_transfer.h"
#include "robot/feasible_motion.h"
#include "robot/rsr_model.h"
#include "src/core/rt/periodic_loop.h"
#include "src/core/rt/snapshot.h"
#include "src/core/rt/spsc_queue.h"
#include "src/teleop/feedback_passivity.h"
#include "src/teleop/leader_config.h"
#include "src/teleop/let_go_detector.h"
#include "src/teleop/link.h"
#include "src/teleop/setpoint_validator.h"

namespace robossis::teleop {

enum class LeaderState : std::uint8_t {
  kWaiting,      // no operator presence: clutch open, no force, the follower holds
  kTracking,     // presence: rendering and sending set-points
  kDeviceFault,  // latched after a device failure until RequestReset()
  kEnded,        // the replay is over: the leader holds
};
const char* ToString(LeaderState state);

// Everything one leader tick saw and did (SI; poses as position + unit quaternion w, x, y, z).
struct LeaderTickRecord {
  std::int64_t t_ns = 0;               // tick start (runtime clock)
  std::int64_t sample_ns = 0;          // the device reading's own time
  std::uint64_t tick = 0;
  std::array<double, 3> p_OH{};        // hand
  std::array<double, 4> q_OH{1, 0, 0, 0};
  std::array<double, 3> v_O{};
  std::array<double, 3> w_O{};
  std::array<double, 3> f_O{};         // force sent to the device (after the limits; zero when zeroed)
  std::array<double, 3> tau_O{};
  std::array<double, 3> p_goal{};      // the pose the motion transfer asks for (where the walls are rendered)
  std::array<double, 4> q_goal{1, 0, 0, 0};
  std::array<double, 3> p_sent{};      // the feasible set-point (last one sent)
  std::array<double, 4> q_sent{1, 0, 0, 0};
  std::array<double, 3> p_follower{};  // the follower's last measured pose
  std::array<double, 4> q_follower{1, 0, 0, 0};
  std::array<double, 6> ideal_disp{};     // eq. 10–11 displacement from the start (the transfer's goal, unfiltered)
  std::array<double, 6> transfer_disp{};  // the transfer's filtered set-point displacement (eq. 12), same frame
  double scale_linear = 1;             // eq. 11
  double scale_angular = 1;
  double hc_speed_m_s = 0;
  std::uint64_t sequence = 0;          // of the last set-point sent
  std::uint32_t buttons = 0;
  std::uint8_t device_status = 0;      // haptics::DeviceStatus
  std::uint8_t haptic_status = 0;      // haptics::HapticStatus
  std::uint8_t leader_state = 0;       // LeaderState
  std::uint8_t follower_state = 0;     // OperatingState (last status seen)
  std::uint8_t flags = 0;              // of the last set-point sent
  std::uint8_t sent_this_tick = 0;     // a set-point went out this tick
  std::uint8_t stopped_at_boundary = 0;  // the set-point was stopped short of the goal
  std::uint8_t force_zeroed = 0;       // the device write sent zero (no presence, failure, forces off)
  // Bilateral feedback: the follower's wrench as received (F), the feedback part of the displayed wrench (O, after
  // the caps and the passivity controller), the port's energies since the start (J) and the observer.
  std::array<double, 6> follower_wrench_F{};
  std::array<double, 6> feedback_wanted_O{};  // the follower's load as the gain and the map make it (before caps)
  std::array<double, 6> feedback_O{};
  double feedback_energy_in_j = 0;
  double feedback_energy_out_j = 0;
  double passivity_observed_j = 0;
  std::uint8_t passivity_active = 0;   // the controller changed the feedback (beyond its tolerance) this tick
  std::uint8_t taper_active = 0;       // its taper alone did
  std::uint8_t feedback_shown = 0;     // the follower's load was shown (bilateral, following, fresh, tracking)
  std::uint8_t let_go = 0;             // the let-go detector believes the operator let go (the device is damped)
  std::int64_t follower_stamp_ns = 0;  // the stamp of the follower status in use (its clock: the delay removed)
};

struct LeaderCounters {
  std::uint64_t ticks = 0;
  std::uint64_t setpoints_sent = 0;
  std::uint64_t stopped_at_boundary = 0;  // set-points stopped short of the goal
  std::uint64_t ik_rejected = 0;          // a candidate failed the final IK check: the last set-point was repeated
  std::uint64_t device_failures = 0;      // transitions into kDeviceFault (each engages the E-stop)
  std::uint64_t records_dropped = 0;      // the flight recorder's queue was full
  std::uint64_t nonfinite_outputs = 0;    // a non-finite force or set-point was produced (and replaced)
  double max_force_n = 0;                 // largest |f| sent to the device
  double max_torque_nm = 0;
  double max_feedback_force_n = 0;        // largest |f| of the feedback part displayed
  std::uint64_t passivity_active_ticks = 0;  // ticks at which the passivity controller changed the feedback
  std::uint64_t taper_active_ticks = 0;      // ticks at which its taper alone did
  double feedback_energy_in_j = 0;        // the feedback port's energies over the whole run (the hand gave; took)
  double feedback_energy_out_j = 0;
  double max_feedback_energy_j = 0;       // the largest (out − in) at any tick (<= 0: passive at every sample)
};

class LeaderUnit final : public rt::PeriodicTask {
 public:
  // `device`, `renderer`, `model` and `link` must outlive the unit. The renderer's rate must be the leader's. The
  // transfer's rate must divide the leader's (the haptic loop may run faster than the 1 kHz that crosses the
  // link). X_FM_start: the follower's pose at the start (feasible). Throws std::invalid_argument.
  LeaderUnit(const LeaderConfig& config, const transfer::TransferConfig& transfer, const robot::RsrModel& model,
             haptics::HapticDevice& device, haptics::HapticRenderer& renderer, LeaderLink& link,
             const Eigen::Isometry3d& X_FM_start, std::uint64_t session_id);

  void Tick(std::int64_t now_ns) noexcept override;

  // Any thread: clears a latched device fault at the next tick (the mapping re-anchors).
  void RequestReset() noexcept { reset_requested_.store(true, std::memory_order_release); }
  // Any thread: the operator's clutch (a control panel's Clutch button). While it is open and the hand is present,
  // the transfer ignores the hand, no force is displayed and the set-points carry presence and the clutch flag (the
  // follower holds in CLUTCHED); closing it re-anchors the mapping, so nothing jumps.
  void RequestClutch(bool open) noexcept { operator_clutch_.store(open, std::memory_order_release); }

  // The flight recorder's consumer end, and the latest record for watchers (any thread).
  rt::SpscQueue<LeaderTickRecord>& records() noexcept { return records_; }
  const rt::Snapshot<LeaderTickRecord>& latest() const noexcept { return latest_; }
  // Read from the loop's thread, or once the loop stopped.
  const LeaderCounters& counters() const noexcept { return counters_; }
  LeaderState state() const noexcept { return state_; }
  // Any thread: follower status messages taken so far (0 until the follower has been heard from).
  std::uint64_t follower_statuses_received() const noexcept {
    return statuses_received_.load(std::memory_order_relaxed);
  }
  int transfer_every() const noexcept { return transfer_every_; }

 private:
  // The pose as the follower receives it (position + quaternion).
  static Eigen::Isometry3d OnTheWire(const Eigen::Isometry3d& X) noexcept;
  bool FeasibleOnTheWire(const Eigen::Isometry3d& X) const noexcept;
  // The goal if feasible, else the boundary point on the segment from the last set-point toward it.
  Eigen::Isometry3d FeasibleToward(const Eigen::Isometry3d& goal, bool& stopped) noexcept;
  // The walls start over with the hand at X_OH and the robot at the last set-point (at the start, on resuming).
  void AnchorWalls(const Eigen::Isometry3d& X_OH) noexcept;
  // Not following: the set-point, the walls and the transfer stay at the robot's measured pose.
  void FollowTheMeasuredRobot(bool status_fresh) noexcept;
  // Whether a set-point at X moving at `twist` can still stop within the acceleration caps before any limit.
  bool StopsInside(const Eigen::Isometry3d& X, const Vector6d& twist) const noexcept;
  // The next set-point toward the feasible `target` within the follower's caps (updates twist_sent_).
  Eigen::Isometry3d WithinFollowerCaps(const Eigen::Isometry3d& target) noexcept;
  void SendSetPoint(std::int64_t sample_ns) noexcept;
  // The follower's load in O (gain and frame map applied), or zero when it must not be shown.
  Vector6d FeedbackWrench(bool shown) const noexcept;

  LeaderConfig config_;
  const robot::RsrModel& model_;
  haptics::HapticDevice& device_;
  haptics::HapticRenderer& renderer_;
  LeaderLink& link_;
  robot::FeasibleMotionGuard guard_;
  transfer::MotionTransfer transfer_;
  transfer::HcToRsrFrame frame_;  // the one HC -> RSR frame map (transfer.yaml mapping), the walls' too
  int transfer_every_;
  double setpoint_period_s_;  // one transfer period: the interval between two set-points
  SetPointLimits follower_limits_;  // the transfer's speed caps, the follower's acceleration caps
  robot::RsrJointVector motor_speeds_;  // the share of the motors' top speeds the set-points keep within
  int actuation_ratio_;
  std::uint64_t session_id_;

  LeaderState state_ = LeaderState::kWaiting;
  bool started_ = false;
  bool clutch_engaged_ = false;
  std::atomic<bool> reset_requested_{false};
  std::atomic<bool> operator_clutch_{false};
  bool clutched_ = false;  // this tick: presence with the operator's clutch open
  Eigen::Isometry3d X_goal_;
  Eigen::Isometry3d X_sent_;
  Vector6d twist_sent_ = Vector6d::Zero();  // the last set-point's twist: its motion over one period
  std::uint64_t sequence_ = 0;
  std::uint8_t last_flags_ = 0;
  FollowerStatusMessage follower_;  // the last status the follower sent
  bool follower_heard_ = false;
  std::int64_t last_status_ns_ = 0;  // when it arrived (this unit's clock)
  bool robot_was_following_ = true;
  std::atomic<std::uint64_t> statuses_received_{0};
  FeedbackPassivity passivity_;
  bool feedback_shown_ = false;      // the feedback was shown at the last tick (its books run)
  LetGoDetector let_go_;
  Eigen::Vector3d f_written_ = Eigen::Vector3d::Zero();  // the force written at the last tick (after the caps)
  Eigen::Vector3d v_read_ = Eigen::Vector3d::Zero();     // the velocity read at the last tick
  double remote_in_base_j_ = 0;      // the follower's input energy when the books started
  LeaderCounters counters_;
  LeaderTickRecord record_;
  rt::SpscQueue<LeaderTickRecord> records_;
  rt::Snapshot<LeaderTickRecord> latest_;
};

// Pose ↔ message arrays (position m, quaternion w, x, y, z).
void PoseToArrays(const Eigen::Isometry3d& X, std::array<double, 3>& p, std::array<double, 4>& q) noexcept;
Eigen::Isometry3d PoseFromArrays(const std::array<double, 3>& p, const std::array<double, 4>& q) noexcept;

}  // namespace robossis::teleop
