#include "src/apps/workspace_json.h"

#include <nlohmann/json.hpp>

#include "haptics/haptics_config.h"
#include "src/core/units.h"

namespace robossis::apps {

using json = nlohmann::ordered_json;

geometry::LiveBoundaryOptions ConfiguredLiveOptions(const AppContext& app) {
  return haptics::HapticsConfig::FromYaml(app.ConfigPath("haptics.yaml")).live;
}

json SliceSummaryJson(const geometry::WorkspaceSlice& slice) {
  const geometry::SliceKind kind = slice.spec.kind;
  const double s = geometry::EdgeUnitScale(kind);
  const std::string unit = geometry::EdgeUnitName(kind);
  const geometry::MeshStatistics& st = slice.stats;
  const Eigen::Vector3d size = (st.max - st.min) * s;
  json j;
  j["slice"] = geometry::ToString(kind);
  j["units"] = unit;
  j["volume"] = st.volume * s * s * s;
  j["volume_unit"] = unit + "^3";
  j["extents"] = {{"min", {st.min.x() * s, st.min.y() * s, st.min.z() * s}},
                  {"max", {st.max.x() * s, st.max.y() * s, st.max.z() * s}},
                  {"size", {size.x(), size.y(), size.z()}}};
  j["triangles"] = st.triangles;
  j["vertices"] = st.vertices;
  j["watertight"] = st.watertight;
  j["outward_oriented"] = st.outward;
  j["degenerate_triangles"] = st.degenerate_triangles;
  if (kind == geometry::SliceKind::kRsrDexterous) {
    j["fixed_rpy_deg"] = {slice.spec.fixed.x() * kRadToDeg, slice.spec.fixed.y() * kRadToDeg,
                          slice.spec.fixed.z() * kRadToDeg};
  } else if (kind == geometry::SliceKind::kRsrRotational) {
    j["fixed_position_mm"] = {slice.spec.fixed.x() * kMToMm, slice.spec.fixed.y() * kMToMm,
                              slice.spec.fixed.z() * kMToMm};
  }
  j["resolution"] = slice.spec.resolution * s;
  j["grid_nodes"] = {slice.grid.dims.x(), slice.grid.dims.y(), slice.grid.dims.z()};
  j["feasible_nodes"] = slice.feasible_nodes;
  j["vertex_max_distance_to_boundary"] = 0.5 * slice.refine_max_bracket * s;
  j["seconds"] = {{"grid", slice.seconds_grid}, {"mesh_and_refine", slice.seconds_mesh}};
  return j;
}

json ErrorStatsJson(const geometry::ErrorStats& e, double scale) {
  return {{"samples", e.samples},        {"not_found", e.not_found}, {"sign_disagreements", e.sign_disagreements},
          {"mean", e.mean * scale},      {"p50", e.p50 * scale},     {"p95", e.p95 * scale},
          {"max", e.max * scale}};
}

json AtlasErrorJson(const geometry::AtlasErrorReport& r) {
  return {{"dexterous_mm", {{"off_grid", ErrorStatsJson(r.dexterous_off_grid, kMToMm)},
                            {"on_grid", ErrorStatsJson(r.dexterous_on_grid, kMToMm)}}},
          {"rotational_deg", {{"off_grid", ErrorStatsJson(r.rotational_off_grid, kRadToDeg)},
                              {"on_grid", ErrorStatsJson(r.rotational_on_grid, kRadToDeg)}}}};
}

json LiveErrorJson(const geometry::ClinicalLiveError& c, const geometry::LiveBoundaryOptions& o) {
  return {{"resolution", {{"dexterous_mm", o.dexterous_resolution_m * kMToMm},
                          {"rotational_deg", o.rotational_resolution_rad * kRadToDeg}}},
          {"tolerance", {{"orientation_deg", o.orientation_tolerance_rad * kRadToDeg},
                         {"position_mm", o.position_tolerance_m * kMToMm}}},
          {"refresh_s", {{"dexterous", c.timing.dexterous_s}, {"rotational", c.timing.rotational_s}}},
          {"clinical_speed", {{"mm_per_s", geometry::kClinicalLinearSpeedMps * kMToMm},
                              {"deg_per_s", geometry::kClinicalAngularSpeedRadps * kRadToDeg}}},
          {"staleness", {{"orientation_deg", c.staleness.orientation_rad * kRadToDeg},
                         {"position_mm", c.staleness.position_m * kMToMm}}},
          {"dexterous_mm", ErrorStatsJson(c.error.dexterous, kMToMm)},
          {"rotational_deg", ErrorStatsJson(c.error.rotational, kRadToDeg)}};
}

}  // namespace robossis::apps
