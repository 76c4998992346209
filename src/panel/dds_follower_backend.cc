#include "src/panel/dds_follower_backend.h"

#include <random>

#include "src/link/dds_leader_link.h"

namespace robossis::panel {
namespace {

constexpr const char* kNoSetPoints =
    "the panel's link credentials grant state commands only, not set-points: the leader moves the robot";

// A random session per panel start, so the follower tells a restarted panel's commands (sequence 1 again) from a
// replay of the old ones.
std::uint64_t DrawCommandSession() {
  std::random_device entropy;
  return (static_cast<std::uint64_t>(entropy()) << 32) | entropy();
}

}  // namespace

DdsFollowerBackend::DdsFollowerBackend(link::LinkOptions options) : command_session_(DrawCommandSession()) {
  options.role = link::Role::kPanel;
  link_ = std::make_unique<link::DdsLeaderLink>(options);
}

DdsFollowerBackend::~DdsFollowerBackend() = default;

bool DdsFollowerBackend::ReadStatus(teleop::FollowerStatusMessage& status) noexcept {
  teleop::FollowerStatusMessage newest;
  if (link_->TakeFollowerStatus(newest)) {
    status_ = newest;
    status_arrival_s_ = clock_.NowS();
    has_status_ = true;
  }
  if (has_status_) status = status_;
  return has_status_;
}

bool DdsFollowerBackend::ReadHealth(LoopHealth& health) noexcept {
  health = LoopHealth{};
  health.setpoint_age_s = status_arrival_s_ < 0 ? -1 : clock_.NowS() - status_arrival_s_;
  return true;
}

bool DdsFollowerBackend::ReadHandWrench(HandWrench& wrench) noexcept {
  wrench = HandWrench{};
  return true;
}

bool DdsFollowerBackend::ReadCommandedPose(Eigen::Isometry3d&) noexcept { return false; }

bool DdsFollowerBackend::SendCommand(teleop::StateCommand command) noexcept {
  teleop::StateCommandMessage message = PanelStateCommand(command, ++command_sequence_, clock_.NowS());
  message.session = command_session_;
  return link_->SendCommand(message);
}

JogVerdict DdsFollowerBackend::PreviewJog(const JogRequest&) {
  JogVerdict verdict;
  verdict.reason = std::string("jog: ") + kNoSetPoints;
  return verdict;
}

JogVerdict DdsFollowerBackend::StartJog(const JogRequest& request) { return PreviewJog(request); }

bool DdsFollowerBackend::RequestHapticMode(const HapticModeRequest& request, std::string& reason) {
  reason.clear();
  if (!request.enabled) return true;  // off is what it is
  reason = std::string("haptic mode: ") + kNoSetPoints;
  return false;
}

}  // namespace robossis::panel
