#pragma once
// What the control panel (paper Fig. 13) needs from the runtime, and nothing more: the follower's latest status
// snapshot, the loop health, state commands, and eq. 9 jogs. The panel's window and its scripted tests talk only to
// this interface, so the same panel runs over the panel's in-process session (LocalSessionBackend: the
// runtime's follower unit and, in haptic mode, its leader unit) or, later, over a remote follower.
//
// Threads: every call comes from the panel's (non-real-time) thread. Reads return copies of atomic snapshots and
// never wait for a loop; commands are queued to the loop through lock-free single-producer structures.

#include <array>
#include <cmath>
#include <cstdint>
#include <string>

#include "src/core/rt/loop_stats.h"
#include "src/panel/jog.h"
#include "src/teleop/link_messages.h"
#include "src/teleop/setpoint_validator.h"

namespace robossis::panel {

// The loop and link health the panel shows. All SI.
struct LoopHealth {
  double period_s = 0;               // nominal loop period
  double max_jitter_s = 0;           // largest |actual period - nominal| since start
  double last_jitter_s = 0;          // the last period's
  std::uint64_t ticks = 0;
  // The deadlines the follower's loop and the leader side's loop (the 1 kHz set-points, where there is one) missed,
  // by cause: a late wake-up (scheduling) or a long tick (rt::LoopStats).
  rt::LoopCounts follower_loop;
  rt::LoopCounts leader_loop;
  double setpoint_age_s = -1;        // time since the last set-point was consumed; < 0: none yet
  std::uint64_t watchdog_holds = 0;  // holds because the set-points went stale
  // The follower's set-points by the validator's verdict (index: teleop::SetPointVerdict): why it refused the ones
  // it refused. Zero where the follower is remote.
  std::array<std::uint64_t, teleop::kNumSetPointVerdicts> setpoints_by_verdict{};
};

// The wrench the haptic device renders on the operator's hand (F in N, M in N·m, fixed frame), for the arrows and
// the plot. Zero when no leader is running.
struct HandWrench {
  std::array<double, 3> force_n{};
  std::array<double, 3> torque_nm{};
};

// Haptic-mode settings the panel asks the leader for (the leader owns them; see haptic_mode.h for the rules).
struct HapticModeRequest {
  bool enabled = false;
  bool clutched = false;
  int rendering_method = 0;  // index into HapticRenderingMethods()
  double max_linear_speed_m_s = 0;
  double max_angular_speed_rad_s = 0;
};

// A state command as the panel sends it: numbered by its backend, stamped on the backend's clock, marked as the
// panel's (for the follower's log).
inline teleop::StateCommandMessage PanelStateCommand(teleop::StateCommand command, std::uint64_t sequence,
                                                     double now_s) {
  teleop::StateCommandMessage message;
  message.sequence = sequence;
  message.stamp_ns = static_cast<std::int64_t>(std::llround(now_s * 1e9));
  message.command = command;
  message.source = teleop::kFromPanel;
  return message;
}

class PanelBackend {
 public:
  virtual ~PanelBackend() = default;
  // The newest follower status; false if none was published yet.
  virtual bool ReadStatus(teleop::FollowerStatusMessage& status) noexcept = 0;
  virtual bool ReadHealth(LoopHealth& health) noexcept = 0;
  virtual bool ReadHandWrench(HandWrench& wrench) noexcept = 0;
  // The pose the follower is commanded to (the jog's or the leader's set-point, or the hold pose); false if none.
  virtual bool ReadCommandedPose(Eigen::Isometry3d& X_FM) noexcept = 0;
  // Queues a state command (source: panel). False if the link refused it (queue full).
  virtual bool SendCommand(teleop::StateCommand command) noexcept = 0;
  // Checks a jog from the follower's current pose without moving anything (the preview).
  virtual JogVerdict PreviewJog(const JogRequest& request) = 0;
  // Checks and starts a jog; a refused jog (the verdict says why) leaves the robot where it is.
  virtual JogVerdict StartJog(const JogRequest& request) = 0;
  // Ends a running jog where it is (the robot holds).
  virtual void StopJog() noexcept = 0;
  // Asks for haptic-mode settings; false with a reason if the owner refused them.
  virtual bool RequestHapticMode(const HapticModeRequest& request, std::string& reason) = 0;
};

}  // namespace robossis::panel
