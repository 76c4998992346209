#pragma once
// `robossis teleop`, `leader`, `follower`, `estop` and `replay` (cmd_teleop.cc).

#include "src/apps/app_context.h"

namespace robossis::apps {

void RegisterTeleopCommands(CLI::App& app, const AppContext& context);

}  // namespace robossis::apps
