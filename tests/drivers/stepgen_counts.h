#pragma once
// Checks on data/hal/robossis-stepgen.hal (LinuxCNC's software stepgen behind the follower's HAL component), for the
// tests that drive it through the runtime. Needs a running HalSession.

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "tests/drivers/hal_session.h"

namespace robossis::testing {

// LinuxCNC's step counts are the commanded joint positions in steps (the eq. 17 count: position-scale is the
// actuation config's steps per unit), within one step per motor. Returns the steps travelled, all motors.
inline double ExpectStepgenCountsMatchTheCommand() {
  double moved_steps = 0;
  for (int m = 0; m < 6; ++m) {
    const std::string g = "stepgen." + std::to_string(m) + ".";
    const double counts = HalSession::GetNumber(g + "counts");
    const double commanded = HalSession::GetNumber(g + "position-cmd") * HalSession::GetNumber(g + "position-scale");
    EXPECT_NEAR(counts, commanded, 1.0) << "motor " << m;
    moved_steps += std::abs(counts);
  }
  return moved_steps;
}

}  // namespace robossis::testing
