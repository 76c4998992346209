#pragma once
// The rendering comparison shared by `robossis render-compare` and the demo's section 3: runs every method on one
// scenario and writes traces, summary.json, summary.md and the Fig. 11 / Fig. 12 analogues into an output folder.

#include <functional>
#include <string>
#include <vector>

#include "haptics/scenarios/compare.h"
#include "src/apps/app_context.h"
#include "src/core/files.h"

namespace robossis::apps {

struct RenderCompareRequest {
  std::string scenario;  // name or FILE.csv
  std::vector<std::string> methods;
  double rate_hz = 1000;
  bool fast = false;
  int trace_decimation = 1;
  // Methods run at a time, each on a thread of its own (haptics::RunMethods): at most the number of cores, so the
  // tick times stay those of a run alone on its core.
  int jobs = 1;
  std::string prefix;  // sub-folder inside the output folder ("" or "rendering/push-edges-1000hz/")
  // Boundary atlas for the mesh method: loaded from atlas_dir if set, else built (coarse with `fast`) into
  // <out>/<prefix>atlas/ — or reused from `atlas` if already loaded.
  std::string atlas_dir;
  std::shared_ptr<const geometry::BoundaryAtlas> atlas;
};

struct RenderCompareResult {
  haptics::Scenario scenario;
  std::vector<haptics::MethodRun> runs;  // metrics per method; their traces are in the output folder, not here
  nlohmann::ordered_json summary;
  std::string table_markdown;
  std::vector<std::string> figures;  // PNGs written (relative to the output folder)
  std::vector<std::string> figure_failures;
  std::shared_ptr<const geometry::BoundaryAtlas> atlas;  // the atlas used (null if no mesh method)
  std::string atlas_source;                               // where it came from, for the report
};

// `figure` renders one PNG: (script, args, png relative path, caption) → success.
using FigureFn = std::function<bool(const std::string&, const std::vector<std::string>&, const std::string&,
                                    const std::string&)>;
RenderCompareResult RunRenderCompare(const AppContext& context, const RenderCompareRequest& request,
                                     const StagedOutputDir& out, const FigureFn& figure,
                                     const std::function<void(const std::string&)>& progress);

}  // namespace robossis::apps
