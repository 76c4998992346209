#pragma once
// `robossis teleop` and `robossis replay` (cmd_teleop.cc).

#include "src/apps/app_context.h"

namespace robossis::apps {

void RegisterTeleopCommands(CLI::App& app, const AppContext& context);

}  // namespace robossis::apps
