// `robossis workspace ...`: workspace slices and their boundary meshes, the boundary atlas, and the signed
// penetration query against it.

#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "geometry/atlas_error.h"
#include "geometry/boundary_atlas.h"
#include "geometry/live_boundary.h"
#include "src/apps/app_context.h"
#include "src/apps/workspace_json.h"
#include "src/core/files.h"
#include "src/core/parse.h"
#include "src/core/units.h"

namespace robossis::apps {

namespace {

using json = nlohmann::ordered_json;

Eigen::Vector3d ParseTriple(const std::string& text, const std::string& option, const std::string& hint,
                            double to_si) {
  const std::vector<double> v = ParseNumberList(text, 3, option, hint, FieldBounds::kWorkspace);
  return Eigen::Vector3d(v[0], v[1], v[2]) * to_si;
}

// Grid spacing of a slice: finer than 0.5 mm or 0.5 deg makes a grid of more than ~1e8 cells (minutes and GBs).
double PositiveResolution(double value, const std::string& option) {
  return OptionInRange(value, 0.5, 50.0, option, option.find("deg") != std::string::npos ? "deg" : "mm");
}

// Writes mesh files and the summary of one slice into the staging folder.
void WriteSlice(const StagedOutputDir& out, const geometry::WorkspaceSlice& slice, const std::string& stem) {
  const double s = geometry::EdgeUnitScale(slice.spec.kind);
  out.Write(stem + ".stl", geometry::BinaryStlBytes(slice.mesh, s));
  out.Write(stem + ".ply", geometry::BinaryPlyBytes(slice.mesh, s));
}

void PrintSliceLine(const geometry::WorkspaceSlice& slice) {
  const double s = geometry::EdgeUnitScale(slice.spec.kind);
  const std::string u = geometry::EdgeUnitName(slice.spec.kind);
  const Eigen::Vector3d size = (slice.stats.max - slice.stats.min) * s;
  std::printf("%s: volume %.6g %s^3, extents %.2f x %.2f x %.2f %s, %zu triangles, watertight %s, outward %s, "
              "%.3f s\n",
              geometry::ToString(slice.spec.kind), slice.stats.volume * s * s * s, u.c_str(), size.x(), size.y(),
              size.z(), u.c_str(), slice.stats.triangles, slice.stats.watertight ? "yes" : "no",
              slice.stats.outward ? "yes" : "no", slice.seconds_grid + slice.seconds_mesh);
}

class ProgressBar {
 public:
  void operator()(int done, int total) const {
    const int width = 40, filled = total > 0 ? width * done / total : width;
    std::fprintf(stderr, "\r[%s%s] %d/%d slices", std::string(filled, '#').c_str(),
                 std::string(width - filled, '.').c_str(), done, total);
    if (done == total) std::fprintf(stderr, "\n");
  }
};

}  // namespace

void RegisterWorkspaceCommands(CLI::App& app, const AppContext& context) {
  CLI::App* ws = app.add_subcommand("workspace", "Workspace slices, boundary meshes, boundary atlas, penetration query");
  ws->require_subcommand(1);

  // dexterous
  struct DexterousOptions {
    std::string rpy = "0,0,0", out;
    double resolution_mm = 2;
    double error_samples = 0;
  };
  auto dex = std::make_shared<DexterousOptions>();
  CLI::App* d = ws->add_subcommand("dexterous", "RSR dexterous workspace (positions of P in F) at a fixed orientation\n"
                                                "Example: robossis workspace dexterous --rpy-deg 0,0,0 --resolution-mm 2 --out dex");
  d->add_option("--rpy-deg", dex->rpy, "Fixed orientation ROLL_DEG,PITCH_DEG,YAW_DEG")->capture_default_str();
  d->add_option("--resolution-mm", dex->resolution_mm, "Grid spacing (mm)")->capture_default_str();
  d->add_option("--out", dex->out, "Output folder: mesh.stl, mesh.ply (mm), summary.json")->required();
  d->add_option("--error-samples", dex->error_samples,
                "Points near the boundary at which the mesh query is compared with the IK reference (summary.json); "
                "0 to " + std::to_string(geometry::kMaxErrorSamples))
      ->capture_default_str();
  d->callback([&context, dex] {
    const int error_samples = geometry::RequireErrorSamples(dex->error_samples, "--error-samples");
    const OutputPolicy output = context.Output();
    output.CheckFolder("--out", dex->out);
    geometry::SliceSpec spec;
    spec.kind = geometry::SliceKind::kRsrDexterous;
    spec.fixed = ParseTriple(dex->rpy, "--rpy-deg", "ROLL_DEG,PITCH_DEG,YAW_DEG", kDegToRad);
    spec.resolution = MmToM(PositiveResolution(dex->resolution_mm, "--resolution-mm"));
    StagedOutputDir out(dex->out, output);
    const robot::RsrModel rsr = context.LoadRsr();
    const robot::Sigma7Model sigma7 = context.LoadSigma7();
    const geometry::WorkspaceSlice slice = geometry::GenerateSlice(rsr, sigma7, spec);
    WriteSlice(out, slice, "mesh");
    json summary = SliceSummaryJson(slice);
    if (error_samples > 0) {
      summary["error_vs_reference_mm"] =
          ErrorStatsJson(geometry::MeasureSliceError(rsr, sigma7, slice, error_samples, 42), kMToMm);
    }
    out.Write("summary.json", summary.dump(2) + "\n");
    out.Commit();
    PrintSliceLine(slice);
  });

  // rotational
  struct RotationalOptions {
    std::string position, out;
    double resolution_deg = 1;
    double error_samples = 0;
  };
  auto rot = std::make_shared<RotationalOptions>();
  CLI::App* r = ws->add_subcommand("rotational", "RSR rotational workspace (roll, pitch, yaw) at a fixed position\n"
                                                 "Example: robossis workspace rotational --position-mm 0,0,284 --resolution-deg 1 --out rot");
  r->add_option("--position-mm", rot->position, "Fixed position X_MM,Y_MM,Z_MM of P in F (default: home)");
  r->add_option("--resolution-deg", rot->resolution_deg, "Grid spacing (deg)")->capture_default_str();
  r->add_option("--out", rot->out, "Output folder: mesh.stl, mesh.ply (deg), summary.json")->required();
  r->add_option("--error-samples", rot->error_samples,
                "Points near the boundary at which the mesh query is compared with the IK reference (summary.json); "
                "0 to " + std::to_string(geometry::kMaxErrorSamples))
      ->capture_default_str();
  r->callback([&context, rot] {
    const int error_samples = geometry::RequireErrorSamples(rot->error_samples, "--error-samples");
    const OutputPolicy output = context.Output();
    output.CheckFolder("--out", rot->out);
    const robot::RsrModel rsr = context.LoadRsr();
    geometry::SliceSpec spec;
    spec.kind = geometry::SliceKind::kRsrRotational;
    spec.fixed = rot->position.empty() ? Eigen::Vector3d(rsr.geometry().X_FM_home.translation())
                                       : ParseTriple(rot->position, "--position-mm", "X_MM,Y_MM,Z_MM", kMmToM);
    spec.resolution = DegToRad(PositiveResolution(rot->resolution_deg, "--resolution-deg"));
    StagedOutputDir out(rot->out, output);
    const robot::Sigma7Model sigma7 = context.LoadSigma7();
    const geometry::WorkspaceSlice slice = geometry::GenerateSlice(rsr, sigma7, spec);
    WriteSlice(out, slice, "mesh");
    json summary = SliceSummaryJson(slice);
    if (error_samples > 0) {
      summary["error_vs_reference_deg"] =
          ErrorStatsJson(geometry::MeasureSliceError(rsr, sigma7, slice, error_samples, 42), kRadToDeg);
    }
    out.Write("summary.json", summary.dump(2) + "\n");
    out.Commit();
    PrintSliceLine(slice);
  });

  // hc
  struct HcOptions {
    std::string out;
    double resolution_mm = 3, resolution_deg = 3;
  };
  auto hc = std::make_shared<HcOptions>();
  CLI::App* h = ws->add_subcommand("hc", "sigma.7 workspaces: delta translation (cone-like) and wrist box\n"
                                         "Example: robossis workspace hc --out hc");
  h->add_option("--resolution-mm", hc->resolution_mm, "Grid spacing of the translation slice (mm)")->capture_default_str();
  h->add_option("--resolution-deg", hc->resolution_deg, "Grid spacing of the wrist slice (deg)")->capture_default_str();
  h->add_option("--out", hc->out, "Output folder: translation.{stl,ply} (mm), wrist.{stl,ply} (deg), summary.json")
      ->required();
  h->callback([&context, hc] {
    const OutputPolicy output = context.Output();
    output.CheckFolder("--out", hc->out);
    const robot::RsrModel rsr = context.LoadRsr();
    const robot::Sigma7Model sigma7 = context.LoadSigma7();
    geometry::SliceSpec t{geometry::SliceKind::kHcTranslation, Eigen::Vector3d::Zero(),
                          MmToM(PositiveResolution(hc->resolution_mm, "--resolution-mm"))};
    geometry::SliceSpec w{geometry::SliceKind::kHcWrist, Eigen::Vector3d::Zero(),
                          DegToRad(PositiveResolution(hc->resolution_deg, "--resolution-deg"))};
    StagedOutputDir out(hc->out, output);
    const geometry::WorkspaceSlice translation = geometry::GenerateSlice(rsr, sigma7, t);
    const geometry::WorkspaceSlice wrist = geometry::GenerateSlice(rsr, sigma7, w);
    WriteSlice(out, translation, "translation");
    WriteSlice(out, wrist, "wrist");
    // The headline keys at the top level describe the translation slice; both slices are under "slices".
    json summary = SliceSummaryJson(translation);
    summary["slices"] = {{"translation", SliceSummaryJson(translation)}, {"wrist", SliceSummaryJson(wrist)}};
    out.Write("summary.json", summary.dump(2) + "\n");
    out.Commit();
    PrintSliceLine(translation);
    PrintSliceLine(wrist);
  });

  // atlas
  struct AtlasOptions {
    std::string out;
    bool coarse = false;
    double error_samples = 40;
  };
  auto at = std::make_shared<AtlasOptions>();
  CLI::App* a = ws->add_subcommand("atlas", "Precompute the boundary atlas (dexterous slices over orientations, "
                                            "rotational slices over positions)\n"
                                            "Example: robossis workspace atlas --out atlas");
  a->add_option("--out", at->out,
                "Atlas folder, atlas_error.json included: built in OUT.partial-PID and moved in whole only when "
                "everything succeeded (a failed or interrupted run leaves OUT as it was)")
      ->required();
  a->add_flag("--coarse", at->coarse, "A small, coarse atlas (seconds; for tests and trials)");
  a->add_option("--error-samples", at->error_samples,
                "Poses per case for the grid-spacing error measurement written to atlas_error.json (0: skip); "
                "at most " + std::to_string(geometry::kMaxErrorSamples))
      ->capture_default_str();
  a->callback([&context, at] {
    const int error_samples = geometry::RequireErrorSamples(at->error_samples, "--error-samples");
    const OutputPolicy output = context.Output();
    output.CheckFolder("--out", at->out);
    // Every config is read before the build, so a bad one is refused before minutes of work.
    const robot::RsrModel rsr = context.LoadRsr();
    const robot::Sigma7Model sigma7 = context.LoadSigma7();
    const geometry::LiveBoundaryOptions live = ConfiguredLiveOptions(context);
    const geometry::AtlasSpec spec = at->coarse ? geometry::AtlasSpec::Coarse(rsr) : geometry::AtlasSpec::Default(rsr);
    // The atlas and its error measurement are one output: committed together, or not at all.
    StagedOutputDir out(at->out, output);
    const geometry::BoundaryAtlas atlas = geometry::BuildAtlasIn(rsr, sigma7, spec, out.staging(), ProgressBar{});
    std::fprintf(stderr, "atlas: %zu dexterous and %zu rotational slices built\n", atlas.dexterous().size(),
                 atlas.rotational().size());
    if (error_samples > 0) {
      std::fprintf(stderr, "measuring the grid-spacing error (%d poses per case)...\n", error_samples);
      geometry::AtlasErrorOptions options;
      options.samples = error_samples;
      json err = AtlasErrorJson(geometry::MeasureAtlasError(rsr, sigma7, atlas, options));
      std::printf("grid-spacing error (off-grid poses): dexterous p95 %.3f mm, max %.3f mm; rotational p95 %.3f "
                  "deg, max %.3f deg\n",
                  err["dexterous_mm"]["off_grid"]["p95"].get<double>(), err["dexterous_mm"]["off_grid"]["max"].get<double>(),
                  err["rotational_deg"]["off_grid"]["p95"].get<double>(),
                  err["rotational_deg"]["off_grid"]["max"].get<double>());
      std::fprintf(stderr, "measuring the live-slice error at clinical speeds (%d poses per family)...\n",
                   error_samples);
      err["live"] = LiveErrorJson(geometry::MeasureClinicalLiveError(rsr, sigma7, spec, live, error_samples), live);
      const json& l = err["live"];
      std::printf("live slices (refreshed at the pose; %.3f s + %.3f s per refresh; staleness %.3f deg / %.2f mm at "
                  "2 mm/s, 0.2 deg/s): dexterous p95 %.3f mm, max %.3f mm; rotational p95 %.3f deg, max %.3f deg\n",
                  l["refresh_s"]["dexterous"].get<double>(), l["refresh_s"]["rotational"].get<double>(),
                  l["staleness"]["orientation_deg"].get<double>(), l["staleness"]["position_mm"].get<double>(),
                  l["dexterous_mm"]["p95"].get<double>(), l["dexterous_mm"]["max"].get<double>(),
                  l["rotational_deg"]["p95"].get<double>(), l["rotational_deg"]["max"].get<double>());
      out.Write("atlas_error.json", err.dump(2) + "\n");
    }
    out.Commit();
    std::printf("atlas: %zu dexterous and %zu rotational slices in %s\n", atlas.dexterous().size(),
                atlas.rotational().size(), at->out.c_str());
  });

  // query
  struct QueryOptions {
    std::string atlas, pose;
    double radius_mm = 0, radius_deg = 0;
    bool json_out = false;
    bool live = false;
  };
  auto qo = std::make_shared<QueryOptions>();
  CLI::App* q = ws->add_subcommand("query", "Signed penetration of a pose against the atlas (positive inside)\n"
                                            "Example: robossis workspace query --atlas atlas --pose 10,0,290,0,5,0 --json");
  q->add_option("--atlas", qo->atlas, "Atlas folder written by `workspace atlas` (optional with --live)");
  q->add_option("--pose", qo->pose, "X_MM,Y_MM,Z_MM,ROLL_DEG,PITCH_DEG,YAW_DEG of the moving ring in F")->required();
  q->add_option("--radius-mm", qo->radius_mm, "Radius of the query sphere in position (mm)")->capture_default_str();
  q->add_option("--radius-deg", qo->radius_deg, "Radius of the query sphere in RPY space (deg)")->capture_default_str();
  q->add_flag("--json", qo->json_out, "Machine-readable output");
  q->add_flag("--live", qo->live,
              "Regenerate both slices at this exact pose (as the live refresh does behind the haptic loop) instead "
              "of using the nearest atlas node: accurate to the mesh error, ~0.1 s");
  q->callback([&context, qo] {
    const Eigen::Isometry3d X_FM = ParsePoseMmDeg(qo->pose, "--pose");
    OptionInRange(qo->radius_mm, 0, 1000, "--radius-mm", "mm");
    OptionInRange(qo->radius_deg, 0, 180, "--radius-deg", "deg");
    if (qo->atlas.empty() && !qo->live) throw std::invalid_argument("--atlas: required unless --live is given");
    const geometry::BoundaryAtlas atlas =
        qo->atlas.empty() ? geometry::BoundaryAtlas() : geometry::BoundaryAtlas::Load(qo->atlas);
    if (!qo->atlas.empty()) atlas.RequireBuiltFor(context.LoadRsr(), context.LoadSigma7(), "--atlas " + qo->atlas);
    // The result points into the slices that answered (the atlas's or the live boundary's), so both owners live
    // until the output is written.
    std::optional<geometry::LiveBoundary> live;
    geometry::PoseBoundaryResult r;
    if (qo->live) {
      live.emplace(context.LoadRsr(), context.LoadSigma7(), ConfiguredLiveOptions(context));
      live->PostPose(X_FM);
      live->RefreshNow();
      geometry::LivePoseQuery query;
      query.Query(*live, qo->atlas.empty() ? nullptr : &atlas, X_FM, MmToM(qo->radius_mm), DegToRad(qo->radius_deg),
                  &r);
    } else {
      geometry::AtlasPoseQuery query;
      query.Query(atlas, X_FM, MmToM(qo->radius_mm), DegToRad(qo->radius_deg), &r);
    }
    auto triple = [](const Eigen::Vector3d& v, double s) { return json::array({v.x() * s, v.y() * s, v.z() * s}); };
    // A pose off the atlas grid is answered by no node: its nearest (clamped) node's slice belongs to another pose
    // (MarkOffGrid: "off_grid", never "ok").
    geometry::MarkOffGrid(qo->atlas.empty() ? nullptr : &atlas, X_FM, &r);
    const bool t_off = r.translation.status == geometry::QueryStatus::kOffGrid;
    const bool r_off = r.rotation.status == geometry::QueryStatus::kOffGrid;
    const bool t_ok = r.translation.status == geometry::QueryStatus::kOk;
    const bool r_ok = r.rotation.status == geometry::QueryStatus::kOk;
    json doc;
    doc["signed_distance_mm"] = t_ok ? json(r.translation.signed_distance * kMToMm) : json(nullptr);
    doc["signed_angle_deg"] = r_ok ? json(r.rotation.signed_distance * kRadToDeg) : json(nullptr);
    doc["normal"] = t_ok ? triple(r.translation.normal, 1.0) : json(nullptr);
    doc["nearest_mm"] = t_ok ? triple(r.translation.nearest, kMToMm) : json(nullptr);
    doc["angle_normal"] = r_ok ? triple(r.rotation.normal, 1.0) : json(nullptr);
    doc["nearest_rpy_deg"] = r_ok ? triple(r.rotation.nearest, kRadToDeg) : json(nullptr);
    // The slices that answered: the live ones (made at this pose) or the nearest atlas nodes.
    const Eigen::Vector3d* dexterous_at = r.live_dexterous_slice ? &r.live_dexterous_slice->fixed
                                          : r.dexterous_slice    ? &r.dexterous_slice->fixed
                                                                 : nullptr;
    const Eigen::Vector3d* rotational_at = r.live_rotational_slice ? &r.live_rotational_slice->fixed
                                           : r.rotational_slice    ? &r.rotational_slice->fixed
                                                                   : nullptr;
    if (t_off) dexterous_at = nullptr;
    if (r_off) rotational_at = nullptr;
    doc["dexterous_slice_rpy_deg"] = dexterous_at ? triple(*dexterous_at, kRadToDeg) : json(nullptr);
    doc["rotational_slice_position_mm"] = rotational_at ? triple(*rotational_at, kMToMm) : json(nullptr);
    doc["live"] = {{"translation", r.live_dexterous_slice != nullptr},
                   {"rotation", r.live_rotational_slice != nullptr}};
    doc["status"] = {{"translation", geometry::ToString(r.translation.status)},
                     {"rotation", geometry::ToString(r.rotation.status)}};
    if (qo->json_out) {
      PrintJson(doc);
    } else {
      for (const auto& [key, value] : doc.items()) std::cout << key << ": " << value.dump() << "\n";
    }
  });
}

}  // namespace robossis::apps
