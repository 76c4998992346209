#pragma once
// The panel as one more participant of the two-machine link (`robossis panel --link dds`): it watches a remote
// follower unit and sends it state commands (E-stop, Home, Enable, Disable, Reset) over Cyclone DDS with the panel's
// own credentials (link::Role::kPanel). Those credentials grant the command topic and the follower's status, not
// the set-points: jogs and haptic mode are refused with the reason (the leader moves the robot).
//
// Threads: every call comes from the panel's thread, which is the link's one status consumer and one command
// producer; the link's own threads do the DDS work (src/link/dds_leader_link.h). Nothing here waits for the network.

#include <cstdint>
#include <memory>

#include "src/core/rt/clock.h"
#include "src/link/link_options.h"
#include "src/panel/panel_backend.h"

namespace robossis::link {
class DdsLeaderLink;
}

namespace robossis::panel {

class DdsFollowerBackend final : public PanelBackend {
 public:
  // Joins the link as the panel (options.role is replaced by kPanel). Throws std::runtime_error on bad options or
  // refused credentials (link::DdsLeaderLink).
  explicit DdsFollowerBackend(link::LinkOptions options);
  ~DdsFollowerBackend() override;

  // The newest status the follower published (kept between calls); false until one arrived.
  bool ReadStatus(teleop::FollowerStatusMessage& status) noexcept override;
  // The remote loops' health is not on the wire: only the age of the newest status is known (in setpoint_age_s's
  // place: how old the picture is), -1 before the first.
  bool ReadHealth(LoopHealth& health) noexcept override;
  bool ReadHandWrench(HandWrench& wrench) noexcept override;              // zero: no hand at the panel
  bool ReadCommandedPose(Eigen::Isometry3d& X_FM) noexcept override;      // false: the set-points are not granted
  bool SendCommand(teleop::StateCommand command) noexcept override;       // source 2, panel; its session, next sequence, stamp
  JogVerdict PreviewJog(const JogRequest& request) override;              // refused
  JogVerdict StartJog(const JogRequest& request) override;                // refused
  void StopJog() noexcept override {}
  bool RequestHapticMode(const HapticModeRequest& request, std::string& reason) override;  // refused

 private:
  rt::MonotonicClock clock_;
  std::unique_ptr<link::DdsLeaderLink> link_;
  bool has_status_ = false;
  teleop::FollowerStatusMessage status_;
  double status_arrival_s_ = -1;
  std::uint64_t command_session_;  // drawn at start: the follower drops a replayed or stale command of a session
  std::uint64_t command_sequence_ = 0;
};

}  // namespace robossis::panel
