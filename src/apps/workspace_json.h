#pragma once
// JSON summaries of workspace slices and atlas errors, shared by `robossis workspace` and the demo report, and the
// configured live-slice options they measure.

#include <nlohmann/json_fwd.hpp>

#include "geometry/atlas_error.h"
#include "geometry/workspace_slice.h"
#include "src/apps/app_context.h"

namespace robossis::apps {

// The live slices as the haptic loop uses them (haptics.yaml, `mesh_live`), so that the error the workspace commands
// report is the error mesh-live renders with.
geometry::LiveBoundaryOptions ConfiguredLiveOptions(const AppContext& app);

// summary.json of one slice: volume, extents, triangles, watertight (the headline keys) plus units and details.
// Edge units: mm (mm^3) for position slices, deg (deg^3) for angle slices.
nlohmann::ordered_json SliceSummaryJson(const geometry::WorkspaceSlice& slice);


nlohmann::ordered_json ErrorStatsJson(const geometry::ErrorStats& s, double scale);
nlohmann::ordered_json AtlasErrorJson(const geometry::AtlasErrorReport& report);
nlohmann::ordered_json LiveErrorJson(const geometry::ClinicalLiveError& live, const geometry::LiveBoundaryOptions& o);

}  // namespace robossis::apps
