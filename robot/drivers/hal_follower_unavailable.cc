// MakeHalFollower where the program was built without LinuxCNC's HAL headers (linuxcnc-uspace-dev).
#include <stdexcept>

#include "robot/drivers/hal_follower.h"

namespace robossis::drivers {

std::unique_ptr<robot::Follower> MakeHalFollower(const robot::RsrModel&, const std::filesystem::path&) {
  throw std::runtime_error(
      "follower 'hal': this build has no LinuxCNC HAL (install linuxcnc-uspace-dev and rebuild)");
}

}  // namespace robossis::drivers
