// `robossis render-compare`: haptic rendering methods side by side on the same closed-loop motion.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "haptics/rendering/renderer_factory.h"
#include "haptics/transfer/transfer_config.h"
#include "src/core/units.h"
#include "src/apps/plotting.h"
#include "src/apps/render_compare.h"

namespace robossis::apps {

RenderCompareResult RunRenderCompare(const AppContext& context, const RenderCompareRequest& request,
                                     const StagedOutputDir& out, const FigureFn& figure,
                                     const std::function<void(const std::string&)>& progress) {
  if (!(request.rate_hz >= 100 && request.rate_hz <= 20000)) {
    throw std::invalid_argument("--rate-hz: expected a haptic rate in [100, 20000] Hz, got " +
                                std::to_string(request.rate_hz));
  }
  const robot::RsrModel rsr = context.LoadRsr();
  const robot::Sigma7Model sigma7 = context.LoadSigma7();
  const haptics::HapticsConfig config = haptics::HapticsConfig::FromYaml(context.ConfigPath("haptics.yaml"));
  RenderCompareResult result;
  result.scenario = haptics::MakeScenario(request.scenario, rsr, config.hand, config.strike_hand_stiffness_n_per_m,
                                          request.fast);
  // "mesh" needs the atlas; "mesh-live" and "mesh-proxy(-safe)" use it until their first refresh lands.
  const auto uses_atlas = [](const std::string& m) { return m.rfind("mesh", 0) == 0; };
  if (std::any_of(request.methods.begin(), request.methods.end(), uses_atlas)) {
    if (request.atlas) {
      result.atlas = request.atlas;
      result.atlas_source = "reused";
    } else if (!request.atlas_dir.empty()) {
      result.atlas = std::make_shared<const geometry::BoundaryAtlas>(geometry::BoundaryAtlas::Load(request.atlas_dir));
      result.atlas->RequireBuiltFor(rsr, sigma7, "--atlas " + request.atlas_dir);
      result.atlas_source = "loaded from " + request.atlas_dir;
    } else {
      // Without --atlas: the geometry module's default atlas (about 20 s of CPU), the coarse one with --fast.
      const geometry::AtlasSpec spec =
          request.fast ? geometry::AtlasSpec::Coarse(rsr) : geometry::AtlasSpec::Default(rsr);
      progress(std::string("render-compare: building the ") + (request.fast ? "coarse" : "default") +
               " boundary atlas for the mesh method (pass --atlas DIR to reuse one)");
      const std::filesystem::path dir = out.Path(request.prefix + "atlas");
      result.atlas = std::make_shared<const geometry::BoundaryAtlas>(geometry::BuildAtlas(rsr, sigma7, spec, dir));
      result.atlas_source = std::string("built (") +
                            (request.fast ? "AtlasSpec::Coarse" : "AtlasSpec::Default") +
                            ") into " + request.prefix + "atlas/";
    }
  }
  haptics::CompareSettings settings;
  settings.rate_hz = request.rate_hz;
  // The hand is placed through the one HC -> RSR frame map, transfer.yaml's, as the teleoperation places it.
  settings.frame = transfer::TransferConfig::FromYaml(context.ConfigPath("transfer.yaml")).mapping.frame();
  settings.trace_decimation = std::max(1, request.trace_decimation);
  const std::string run_name = "render-compare: " + result.scenario.name + " at " +
                               std::to_string(static_cast<int>(request.rate_hz)) + " Hz, method ";
  const auto trace_of = [&request](const std::string& method) { return request.prefix + "traces/" + method + ".csv"; };
  haptics::MethodRunEvents events;
  events.started = [&](std::size_t i) { progress(run_name + request.methods[i]); };
  events.done = [&](std::size_t i, haptics::MethodRun& run, double wall_s) {
    out.Write(trace_of(request.methods[i]), haptics::TraceCsv(run));
    // The trace is in its file (the figures read it there); the summary and the table need the metrics alone. Held
    // for every method until the scenario's end, the traces were about 80 MB of the demo's peak.
    std::vector<haptics::TickRecord>().swap(run.trace);
    char took[32];
    std::snprintf(took, sizeof took, "%.1f", wall_s);
    progress(run_name + request.methods[i] + " took " + took + " s");
  };
  result.runs = haptics::RunMethods(result.scenario, request.methods, config, rsr, sigma7, settings, result.atlas,
                                    request.jobs, events);
  std::string traces, labels;
  for (const std::string& method : request.methods) {
    traces += (traces.empty() ? "" : ",") + out.Path(trace_of(method)).string();
    labels += (labels.empty() ? "" : ",") + method;
  }
  result.summary = haptics::SummaryJson(result.scenario, settings, result.runs);
  out.Write(request.prefix + "summary.json", result.summary.dump(2) + "\n");
  result.table_markdown = haptics::MarkdownTable(result.runs);
  out.Write(request.prefix + "summary.md", "# Rendering comparison: " + result.scenario.name + " at " +
                                                std::to_string(static_cast<int>(request.rate_hz)) + " Hz\n\n" +
                                                result.table_markdown + "\n" + haptics::MarkdownReferenceNotes());
  bool any_push = false;
  for (const haptics::Episode& e : result.scenario.episodes) any_push = any_push || e.is_push;
  auto draw = [&](const std::string& script, const std::string& png, const std::string& caption) {
    const std::string rel = request.prefix + png;
    if (figure(script, {"--traces", traces, "--labels", labels, "--title", result.scenario.name}, rel, caption)) {
      result.figures.push_back(rel);
    } else {
      result.figure_failures.push_back(rel);
    }
  };
  if (any_push) {
    draw("render_fig11.py", "fig11_force_vs_boundary.png",
         "Fig. 11 analogue: force and torque versus the signed distance to the true boundary (" +
             result.scenario.name + ")");
  }
  draw("render_fig12.py", "fig12_time_series.png",
       "Fig. 12 analogue: RSR joints and the force/torque on the hand over time (" + result.scenario.name + ")");
  return result;
}

void RegisterRenderCompareCommand(CLI::App& app, const AppContext& context) {
  struct Options {
    std::string scenario = "push-edges";
    std::string methods;
    double rate_hz = 1000;
    std::string out = "render-compare";
    bool fast = false;
    bool json = false;
    int trace_decimation = 5;
    int jobs = 1;
    std::string atlas;
  };
  auto options = std::make_shared<Options>();
  for (const std::string& m : haptics::KnownMethods()) options->methods += (options->methods.empty() ? "" : ",") + m;
  CLI::App* cmd = app.add_subcommand(
      "render-compare",
      "Compare haptic rendering methods on the same closed-loop motion (simulated sigma.7 + hand)\n"
      "Example: robossis render-compare --scenario push-edges --methods pointcloud,proxy --rate-hz 1000 --out cmp");
  cmd->add_option("--scenario", options->scenario, "push-edges | explore | strike | FILE.csv (t_s,x_mm,...,yaw_deg)")
      ->capture_default_str();
  cmd->add_option("--methods", options->methods,
                  "Comma-separated methods, each once, no empty entry: " + haptics::KnownMethodsText())
      ->capture_default_str();
  cmd->add_option("--rate-hz", options->rate_hz, "Haptic loop rate (Hz), e.g. 1000 or 4000")->capture_default_str();
  cmd->add_option("--out", options->out, "Output folder (written atomically)")->capture_default_str();
  cmd->add_option("--trace-decimation", options->trace_decimation, "Keep every n-th tick in the traces (the metrics use every tick)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--atlas", options->atlas,
                  "Boundary atlas folder for the mesh method (robossis workspace atlas --out DIR); built if absent")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--jobs", options->jobs,
                  "Methods run at a time, one thread each (same results; keep it at most the number of cores, so "
                  "each method's ticks have a core of their own)")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd->add_flag("--fast", options->fast, "Fewer edges and shorter paths");
  cmd->add_flag("--json", options->json, "Print summary.json to stdout");
  cmd->callback([&context, options] {
    RenderCompareRequest request;
    request.scenario = options->scenario;
    request.methods = haptics::ParseMethodList(options->methods, "--methods");
    request.rate_hz = options->rate_hz;
    request.fast = options->fast;
    request.trace_decimation = options->trace_decimation;
    request.jobs = options->jobs;
    request.atlas_dir = options->atlas;
    // A --scenario that names an existing path is a CSV file this run reads.
    std::error_code ec;
    const bool scenario_is_file = std::filesystem::exists(options->scenario, ec);
    const OutputPolicy output =
        context.Output({{"--atlas", options->atlas, true}, {"--scenario", scenario_is_file ? options->scenario : ""}});
    StagedOutputDir out(options->out, output);
    auto figure = [&out](const std::string& script, const std::vector<std::string>& args, const std::string& png,
                         const std::string&) {
      std::vector<std::string> full = args;
      full.push_back("--out");
      full.push_back(out.Path(png).string());
      const PlotResult r = RunPlotScript(script, full);
      if (!r.ok) std::cerr << "render-compare: warning: " << png << " not rendered: " << r.message << "\n";
      return r.ok;
    };
    const RenderCompareResult result =
        RunRenderCompare(context, request, out, figure, [](const std::string& m) { std::cerr << m << std::endl; });
    out.Commit();
    if (options->json) {
      PrintJson(result.summary);
    } else {
      std::cout << result.table_markdown << "\nWritten to " << out.target().string() << "\n";
    }
  });
}

}  // namespace robossis::apps
