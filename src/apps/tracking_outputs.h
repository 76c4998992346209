#pragma once
// Files of a tracking evaluation, shared by `robossis track-eval` and the demo's tracking section.

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "calibration/tracking_eval.h"
#include "src/core/files.h"

namespace robossis::apps {

// Writes <prefix>summary.json, errors.csv, reference.tum, tracked.tum into `out` (a staged folder).
void WriteTrackingOutputs(const calibration::TrackingEvalResult& result, const nlohmann::ordered_json& inputs,
                          const StagedOutputDir& out, const std::string& prefix);

// Arguments for scripts/plots/tracking_fig14.py reading those files.
std::vector<std::string> TrackingFigureArgs(const StagedOutputDir& out, const std::string& prefix,
                                            const std::string& title);

}  // namespace robossis::apps
