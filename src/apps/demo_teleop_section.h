#pragma once
// Demo section 8: teleoperation, the leader and follower units in real time (demo_teleop_section.cc).

#include "src/apps/demo.h"

namespace robossis::apps {

void WriteTeleopSection(DemoContext& demo);  // ## 8. Teleoperation (src/teleop)

}  // namespace robossis::apps
