#pragma once
// What crosses between the leader unit and the follower unit (Fig. 2), sized and shaped to travel over a network at
// 1 kHz: plain fixed-size records, no pointers, SI units, positions in m, orientations as unit quaternions
// (w, x, y, z). The in-process link passes them through lock-free structures; the DDS link maps them one to one
// onto its IDL types (src/link/).
//
// The split follows the paper: the leader renders the walls and runs the motion transfer, so it sends a feasible
// RSR pose set-point with its twist; the follower validates it and runs the 10 kHz actuation (eq. 15–17).
//
// Time stamps are the sender's runtime clock (ns). Two machines' clocks are not the same clock: the follower judges
// freshness by its own clock at arrival and by the sequence number, and uses the sender's stamp only to order and
// to measure the interval between set-points.

#include <array>
#include <cstdint>

namespace robossis::teleop {

// The follower's operating state, as dVRK's CRTK `operating_state` names them.
enum class OperatingState : std::uint8_t {
  kDisabled,  // drives off
  kHoming,    // referencing the joints
  kReady,     // homed, drives on, holding; waits for operator presence and an enable
  kEnabled,   // following the leader's set-points
  kClutched,  // the operator released the clutch: the robot holds, the hand moves freely, re-anchor on re-engage
  kFault,     // a latched fault (the reason is kept); reset to leave
  kEStop,     // latched emergency stop; reset to leave
};
const char* ToString(OperatingState state);

// Commands to the follower's state machine (CRTK `state_command`).
enum class StateCommand : std::uint8_t { kEnable, kDisable, kHome, kEStop, kReset };
const char* ToString(StateCommand command);

// Why the follower unit faulted or refused a set-point.
enum class FaultReason : std::uint8_t {
  kNone,
  kBackEnd,           // the follower back end reported a fault (robot::FollowerFault says which)
  kDeviceFailure,     // the leader's device failed (stale, NaN, lost): the leader asked for a hold
  kSetPointInvalid,   // a set-point was not finite or outside the workspace
  kSetPointTooFast,   // a set-point broke the speed or acceleration caps
  kLeaderLost,        // no set-point for longer than the link timeout
  kEStop,             // an E-stop command
  kNotHomed,          // an enable was refused: the robot is not homed (send home first); the state is unchanged
};
const char* ToString(FaultReason reason);

// Set-point flags.
inline constexpr std::uint8_t kSetPointClutched = 1u << 0;  // clutch open: hold, then re-anchor
inline constexpr std::uint8_t kSetPointPresence = 1u << 1;  // operator presence (the sigma.7's button)
inline constexpr std::uint8_t kSetPointDeviceFault = 1u << 2;  // the leader's device failed: hold (FaultReason::kDeviceFailure)
// The network form of the feedback port's passivity runs (leader.yaml feedback.passivity network, bilateral): the
// follower bounds what it gives the environment by the hand's energy the set-point carries (follower_passivity.h).
inline constexpr std::uint8_t kSetPointEnergyBudget = 1u << 3;

// Leader → follower, every leader tick (CRTK `servo_cp` with a sequence number and a twist).
struct SetPointMessage {
  std::uint64_t sequence = 0;       // strictly increasing per leader session
  std::uint64_t leader_session = 0; // a random id drawn when the leader starts: a restarted leader is a new session
  std::int64_t stamp_ns = 0;        // leader clock at the tick's device read
  std::array<double, 3> p_FM{};     // RSR moving-ring position in F (m)
  std::array<double, 4> q_FM{1, 0, 0, 0};  // orientation, unit quaternion (w, x, y, z)
  std::array<double, 6> twist_F{};  // [v (m/s); omega (rad/s)] in F
  std::uint8_t flags = 0;           // kSetPointClutched | kSetPointPresence | ...
  // The energy the hand has put into the leader's feedback port since this leader session started (J), divided by
  // the feedback gain: what the follower's port may give the environment (the network form of Artigas et al. 2011
  // sends the energies with every packet). Read only with kSetPointEnergyBudget.
  double hand_energy_in_j = 0;
};

// Who sent a state command: carried on the wire (one byte) for the follower's log. It proves nothing: over DDS the
// follower's access control decides who may command (only the panel's credentials may publish state_command).
enum CommandSource : std::uint8_t { kFromCommandLine = 0, kFromLeader = 1, kFromPanel = 2 };

// Any participant → follower (CRTK `state_command`).
struct StateCommandMessage {
  std::uint64_t session = 0;        // a random id drawn when the sender starts: a restarted sender is a new session
  std::uint64_t sequence = 0;       // strictly increasing per session
  std::int64_t stamp_ns = 0;        // sender clock; with the sequence, lets the follower drop replayed or stale commands
  StateCommand command = StateCommand::kDisable;
  std::uint8_t source = kFromCommandLine;  // a CommandSource
};

// The limits the follower validates set-points against (SI), carried by every status: a leader on another machine
// compares its own copy with them before it starts (follower_limits.h).
struct FollowerLimits {
  double max_linear_speed_m_s = 0;
  double max_angular_speed_rad_s = 0;
  double max_linear_accel_m_s2 = 0;
  double max_angular_accel_rad_s2 = 0;
  double max_age_s = 0;                     // a set-point older than this at use is stale
  std::uint64_t model_fingerprint = 0;      // of the robot's config (rsr.yaml, actuation.yaml): ModelFingerprint
};

// Where a status's external wrench comes from.
enum class WrenchSource : std::uint8_t {
  kNone,          // no wrench: the follower is not following (not enabled, clutched, holding): the leader shows none
  kDriveEfforts,  // the drives' efforts through the statics (wrench_estimate.h): the simulation's drive forces
  kForceSensor,   // a force sensor between the ring and the fragment (none is configured yet)
};

// Follower → leader and watchers, at >= 100 Hz (CRTK `measured_cp`, `measured_js`, `operating_state`).
struct FollowerStatusMessage {
  std::uint64_t sequence = 0;
  std::int64_t stamp_ns = 0;                // follower clock (over DDS: plus FollowerLink::StatusStampOffsetNs,
                                            // the system clock's offset from it: measured_cp.header)
  std::array<double, 3> p_FM{};             // measured moving-ring pose
  std::array<double, 4> q_FM{1, 0, 0, 0};
  std::array<double, 6> joints{};           // measured actuated joints, eq. 13 order (rad, m)
  std::array<double, 6> effort{};           // N·m, N
  OperatingState state = OperatingState::kDisabled;
  FaultReason fault_reason = FaultReason::kNone;
  std::uint8_t back_end_fault = 0;          // robot::FollowerFault
  bool homed = false;                       // the back end's joints are referenced (robot::RsrFollowerState)
  std::uint64_t setpoints_accepted = 0;
  std::uint64_t setpoints_rejected = 0;
  std::uint64_t watchdog_holds = 0;
  std::uint64_t last_sequence = 0;          // sequence of the last accepted set-point
  FollowerLimits limits;
  // The external wrench on the moving ring, its own weight removed: [force at P (N); moment about P (N·m)] in F
  // (CRTK `measured_cf`). Zero unless wrench_source says where it came from.
  std::array<double, 6> wrench_F{};
  WrenchSource wrench_source = WrenchSource::kNone;
  // The follower port's energies since the follower started (J), for the leader's passivity observer in its
  // network form (feedback_passivity.h): energy the environment put into the robot (W·v > 0: it entered the
  // network) and energy the robot put into the environment.
  double port_energy_in_j = 0;
  double port_energy_out_j = 0;
};

}  // namespace robossis::teleop
