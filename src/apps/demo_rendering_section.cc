// Demo report, section 3: haptic rendering of the RSR workspace, the paper's point clouds versus our methods.

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "haptics/rendering/renderer_factory.h"
#include "haptics/scenarios/compare.h"
#include "src/apps/demo.h"
#include "src/apps/render_compare.h"

namespace robossis::apps {

void WriteRenderingSection(DemoContext& demo) {
  std::ostringstream& r = demo.report;
  r << "## 3. Haptic rendering\n\n"
    << "The surgeon's hand is kept inside the RSR's pose-dependent workspace by haptic walls (paper §VI, Algorithm 1, "
       "eq. 18–21, Fig. 10–12). Each method runs in closed loop with a simulated sigma.7 held by a simulated hand "
       "(mass-spring-damper driven toward scripted targets; device limits 20 N / 0.4 N·m, delta workspace, wrist "
       "ranges). Every metric is measured against the TRUE boundary (IK feasibility with bisection), not against "
       "any method's own estimate. Methods:\n\n"
    << "- `pointcloud`: the paper's method — two spherical point clouds (15 mm, 5°), each point checked with the "
       "RSR feasibility test, eq. 20 depth from the points inside, eq. 18–19 with k_f 2000 N/m, c_f 15 N·s/m, "
       "k_τ 0.12 N·m/deg, c_τ 0.001 N·m·s/deg, weighted moving average (window 5), caps 15 N / 0.3 N·m;\n"
    << "- `pointcloud-safe`: the same with the device-safe preset (k_τ 1 N·m/rad instead of 6.9);\n"
    << "- `pointcloud-pc`: the paper's method with a time-domain passivity observer + controller;\n"
    << "- `mesh`: mesh walls — the same eq. 18–19, moving average and caps, driven by the geometry module's FCL "
       "signed penetration against the precomputed boundary atlas (nearest grid node);\n"
    << "- `mesh-live`: the same walls on slices regenerated at the current pose in the background (geometry "
       "module's live boundary; in these simulations each refresh lands after a modelled latency, "
       "`mesh_live.simulated_refresh_latency_s` in haptics.yaml), the atlas answering until the first one lands;\n"
    << "- `mesh-proxy`: a god-object on the same meshes — slices regenerated around the proxy, the mesh's nearest "
       "point giving the direction back inside and the exact IK the true boundary along it, the proxy's virtual "
       "coupling through a passive force-rate shaper (0.5 N per 1 kHz tick); `mesh-proxy-safe`: the same with the "
       "device-safe preset, the hardware default;\n"
    << "- `proxy`: ours — a god-object kept on the true boundary by bisection on the IK feasibility, sliding "
       "along the boundary's exact normal, virtual coupling with the paper's constants;\n"
    << "- `proxy-safe` / `proxy-pc`: ours with the device-safe preset, without / with the passivity controller.\n\n"
    ;

  struct Run {
    const char* scenario;
    double rate_hz;
    const char* title;
    bool core_methods_only = false;  // the paper's method, mesh walls and ours only
  };
  std::vector<Run> runs = {{"push-edges", 1000, "Pushing into every workspace edge (Fig. 11), 1 kHz"},
                           {"explore", 1000, "Exploring along the boundary (Fig. 12), 1 kHz"},
                           {"strike", 1000, "A 100 mm/s strike into the +x edge, firm grip, 1 kHz"},
                           {"strike", 4000, "The same strike with a 4 kHz haptic loop", true}};
  if (demo.fast) runs = {{"push-edges", 1000, "Pushing into two edges (x+, roll+), 1 kHz, fast"}};
  // --fast: the paper's method, mesh walls and ours (the presets and passivity variants only in the full report).
  const std::vector<std::string> core_methods = {"pointcloud", "mesh", "mesh-live", "mesh-proxy", "proxy", "proxy-pc"};
  const std::vector<std::string> all_methods = demo.fast ? core_methods : haptics::KnownMethods();
  // The methods of a run are independent: one per core at a time (same metrics and traces; on an idle machine each
  // method's ticks have a core of their own). The rendering is the longest section of the demo.
  const int jobs = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::shared_ptr<const geometry::BoundaryAtlas> atlas;  // built by the first run, reused by the others
  std::string atlas_note;
  for (const Run& run : runs) {
    const std::vector<std::string>& methods = run.core_methods_only ? core_methods : all_methods;
    std::string methods_arg;
    for (const std::string& m : methods) methods_arg += (methods_arg.empty() ? "" : ",") + m;
    RenderCompareRequest request;
    request.scenario = run.scenario;
    request.methods = methods;
    request.rate_hz = run.rate_hz;
    request.fast = demo.fast;
    request.trace_decimation = static_cast<int>(run.rate_hz / 100);
    request.jobs = jobs;
    char folder[96];
    std::snprintf(folder, sizeof folder, "rendering/%s-%dhz/", run.scenario, static_cast<int>(run.rate_hz));
    request.prefix = folder;
    request.atlas = atlas;
    // Section 2 built the same atlas (the default one, the coarse one with --fast): loaded, not built again.
    const std::filesystem::path section2_atlas = demo.out.Path("workspace/atlas");
    if (!atlas && std::filesystem::exists(section2_atlas)) request.atlas_dir = section2_atlas.string();
    // Figures are rendered after the table is written, so they appear below it in the report.
    struct PendingFigure {
      std::string script, png, caption;
      std::vector<std::string> args;
    };
    std::vector<PendingFigure> figures;
    auto collect = [&figures](const std::string& script, const std::vector<std::string>& args,
                              const std::string& png, const std::string& caption) {
      figures.push_back({script, png, caption, args});
      return true;
    };
    const RenderCompareResult result =
        RunRenderCompare(demo.app, request, demo.out, collect, [&demo](const std::string& m) { demo.Progress(m); });
    if (!atlas && result.atlas) {
      atlas = result.atlas;
      atlas_note = request.atlas_dir.empty() ? result.atlas_source : "section 2's, loaded from workspace/atlas/";
      r << "The mesh method's boundary atlas was " << atlas_note << " (" << atlas->dexterous().size()
        << " dexterous and " << atlas->rotational().size() << " rotational slices"
        << (demo.fast ? "; the coarse atlas of `--fast`" : "") << ").\n\n";
    }
    r << "### " << run.title << "\n\n"
      << "Simulated " << result.scenario.duration_s() << " s per method. Reproduce: `robossis render-compare "
      << "--scenario " << run.scenario << " --methods " << methods_arg << " --rate-hz " << run.rate_hz
      << (demo.fast ? " --fast" : "") << " --jobs " << jobs << " --out DIR`. Data: `" << folder << "`.\n\n"
      << result.table_markdown << "\n";
    for (const PendingFigure& f : figures) demo.Figure(f.script, f.args, f.png, f.caption);
  }
  r << haptics::MarkdownReferenceNotes() << "\n";
  r << "Reading the tables: the point clouds start pushing up to 15 mm (5°) before the true boundary, so the HC "
       "barely crosses it but the usable workspace shrinks; the proxy lets the hand reach the true boundary and "
       "resists with a force along the exact normal, growing continuously from zero; the passivity controller "
       "removes the energy a sampled wall can inject. The mesh walls reach the boundary too, but inherit the "
       "meshes' errors: the atlas node's slice jumps as the pose crosses between nodes (`mesh`), and even slices "
       "regenerated at the pose (`mesh-live`) misplace the wall where the region is thin and moves fast (near the "
       "tilt limit, at the scenarios' 1°/s) or comes to a sharp tip (the yaw limit in RPY space) — see "
       "haptics/README.md. Tick times are wall-clock on this machine, shared by other "
       "jobs, with as many methods running at a time as it has cores (`--jobs`; see BENCHMARKS.md for the isolated "
       "benchmark).\n\n";
}

}  // namespace robossis::apps
