#pragma once
// Demo section 8: teleoperation, the leader and follower units in real time (demo_teleop_section.cc).

#include <string>

#include <nlohmann/json.hpp>

#include "src/apps/demo.h"

namespace robossis::apps {

void WriteTeleopSection(DemoContext& demo);  // ## 8. Teleoperation (src/teleop)

// The run's verdict (teleop::RunVerdict, from a follower's summary.json) as a report line, and a fault for the demo
// to flag when the follower did not follow to the end: "**FAULT**: ..." (section names the section in the fault).
void ReportRunVerdict(DemoContext& demo, const nlohmann::ordered_json& follower_summary, const std::string& section);

// A loop's overruns from a session's summary.json, split by cause: "N of M ticks (late wake-up A, long tick B)";
// `loop` is leader, follower or plant.
std::string OverrunsByCause(const nlohmann::ordered_json& summary, const std::string& loop);

}  // namespace robossis::apps
