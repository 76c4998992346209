#pragma once
// One E-stop from the command line (`robossis estop`): joins as the panel participant (its credentials), engages
// the E-stop on the link (the estop topic, DdsLeaderLink::SendEStop) and waits for the follower to report it. Not
// real time; the caller parses and prints.

#include "src/link/link_options.h"
#include "src/teleop/link_messages.h"

namespace robossis::link {

struct EStopSendResult {
  bool follower_heard = false;  // an operating state arrived from a follower
  bool confirmed = false;       // ... and it says ESTOP
  teleop::OperatingState last_state = teleop::OperatingState::kDisabled;
};

// Sends one E-stop and waits up to `timeout_s` for the follower's operating state to say ESTOP. The E-stop sample
// stays offered (transient-local) to a follower that joins while this waits. Throws std::runtime_error on bad
// options or refused credentials.
EStopSendResult SendEStopAndConfirm(const LinkOptions& options, double timeout_s);

}  // namespace robossis::link
