#include "src/link/estop_sender.h"

#include <chrono>
#include <thread>

#include "src/link/dds_leader_link.h"

namespace robossis::link {

EStopSendResult SendEStopAndConfirm(const LinkOptions& options, double timeout_s) {
  LinkOptions o = options;
  o.role = Role::kPanel;  // the command line holds the panel's credentials: commands and status, no set-points
  DdsLeaderLink link(o);
  link.SendEStop();
  EStopSendResult result;
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  teleop::FollowerStatusMessage status;
  while (std::chrono::steady_clock::now() < until) {
    if (link.TakeFollowerStatus(status) && link.Statistics().state_received > 0) {
      result.follower_heard = true;
      result.last_state = status.state;
      if (status.state == teleop::OperatingState::kEStop) {
        result.confirmed = true;
        break;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return result;
}

}  // namespace robossis::link
