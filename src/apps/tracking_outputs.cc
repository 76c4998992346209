#include "src/apps/tracking_outputs.h"

#include <nlohmann/json.hpp>

#include "calibration/tracking_report.h"

namespace robossis::apps {

void WriteTrackingOutputs(const calibration::TrackingEvalResult& result, const nlohmann::ordered_json& inputs,
                          const StagedOutputDir& out, const std::string& prefix) {
  nlohmann::ordered_json summary = calibration::TrackingSummaryJson(result);
  summary["inputs"] = inputs;
  out.Write(prefix + "summary.json", summary.dump(2) + "\n");
  out.Write(prefix + "errors.csv", calibration::TrackingErrorsCsv(result));
  out.Write(prefix + "reference.tum", calibration::ReferenceTum(result));
  out.Write(prefix + "tracked.tum", calibration::TrackedTum(result));
}

std::vector<std::string> TrackingFigureArgs(const StagedOutputDir& out, const std::string& prefix,
                                            const std::string& title) {
  return {"--errors", out.Path(prefix + "errors.csv").string(), "--summary",
          out.Path(prefix + "summary.json").string(), "--title", title};
}

}  // namespace robossis::apps
