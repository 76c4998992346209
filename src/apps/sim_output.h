#pragma once
// Outputs of a simulation run (robossis sim and the demo's section 5): the trajectory CSV, summary.json with the
// issue's seven keys, details.json with everything else, the altered bone fragments with their notice, and the
// Fig. 7 analogue drawn by scripts/plots/sim_fig7.py.

#include <string>

#include <nlohmann/json_fwd.hpp>

#include "robot/sim/scenario.h"
#include "src/apps/plotting.h"
#include "src/core/files.h"

namespace robossis::apps {

// The headline keys: max/mean translation (mm) and rotation (deg) error, max actuator force (N) and torque
// (N·m), real-time factor.
nlohmann::ordered_json SimSummaryJson(const sim::ScenarioSummary& summary);
// Parameters, limits reached, statics check, contact, traction peaks, masses.
nlohmann::ordered_json SimDetailsJson(const sim::ScenarioResult& result, const sim::SimConfig& config);

// Writes <prefix>trajectory.csv, <prefix>summary.json, <prefix>details.json into `out`, and renders
// <prefix>fig7_sim.png. Returns the plot result (the data files are written either way).
PlotResult WriteSimOutputs(const StagedOutputDir& out, const std::string& prefix, const sim::ScenarioResult& result,
                           const sim::SimConfig& config);

// fragment_proximal.stl, fragment_distal.stl (altered versions of FemurR.stl, marked) and NOTICE_femur.txt.
void WriteFragments(const StagedOutputDir& out, const std::string& prefix, const sim::BoneFragments& fragments,
                    const sim::SimConfig& config);

}  // namespace robossis::apps
