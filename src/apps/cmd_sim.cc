// `robossis sim`: the Bullet simulation of the RSR moving the distal femur fragment against muscle traction.

#include <iostream>
#include <memory>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "robot/sim/scenario.h"
#include "src/apps/app_context.h"
#include "src/apps/rsr_json.h"
#include "src/apps/sim_output.h"
#include "src/core/config.h"
#include "src/core/parse.h"

namespace robossis::apps {

void RegisterSimCommands(CLI::App& app, const AppContext& context) {
  struct Options {
    std::string scenario = "sinusoid";
    std::string load_n = "0";
    std::string load_nm = "0";
    std::string duration_s = "30";
    std::string out = "sim-out";
    bool no_gravity = false;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "sim", "Bullet simulation of the RSR carrying the distal femur fragment (paper §IV, Fig. 7)\n"
             "Example: robossis sim --scenario reduction --load-n 517 --load-nm 74 --duration-s 20 --out sim-out");
  cmd->add_option("--scenario", o->scenario, "sinusoid (Fig. 7, six DOF) or reduction (displaced to aligned)")
      ->capture_default_str();
  cmd->add_option("--load-n", o->load_n, "Muscle traction force at the scenario's reference pose, N (paper: 517)")
      ->capture_default_str();
  cmd->add_option("--load-nm", o->load_nm, "Muscle traction torque about the femur, N·m (paper: 74)")
      ->capture_default_str();
  cmd->add_option("--duration-s", o->duration_s, "Simulated time, s")->capture_default_str();
  cmd->add_option("--out", o->out, "Output folder (written atomically: complete or untouched)")->capture_default_str();
  cmd->add_flag("--no-gravity", o->no_gravity, "Switch gravity off");
  cmd->add_flag("--json", o->json, "Print summary.json to stdout");
  cmd->callback([&context, o] {
    const OutputPolicy output = context.Output();
    output.CheckFolder("--out", o->out);
    sim::ScenarioParams params;
    params.kind = sim::ParseScenarioKind(o->scenario);
    params.load_n = ParseNumber(o->load_n, "--load-n");
    params.load_nm = ParseNumber(o->load_nm, "--load-nm");
    params.duration_s = ParseNumber(o->duration_s, "--duration-s");
    params.gravity = !o->no_gravity;
    const robot::RsrModel model = context.LoadRsr();
    const sim::SimConfig config = sim::LoadSimConfig(context.ConfigPath("sim.yaml"), context.data_dir);
    sim::ValidateScenarioParams(params, config);
    StagedOutputDir out(o->out, output);
    std::cerr << "[sim] building the femur fragments and the Bullet model" << std::endl;
    const sim::BoneFragments fragments = sim::BuildBoneFragments(config, model);
    const sim::ScenarioResult result = sim::RunScenario(model, config, fragments, params, [](double f) {
      std::cerr << "\r[sim] " << static_cast<int>(100 * f + 0.5) << "%" << std::flush;
    });
    std::cerr << "\n";
    WriteFragments(out, "", fragments, config);
    const PlotResult plot = WriteSimOutputs(out, "", result, config);
    if (!plot.ok) std::cerr << "[sim] warning: fig7_sim.png not rendered: " << plot.message << "\n";
    out.Commit();
    const sim::ScenarioSummary& s = result.summary;
    if (s.actuator_limit_reached) std::cerr << "[sim] WARNING: " << s.actuator_limit_message << "\n";
    if (s.spherical_limit_exceeded) std::cerr << "[sim] WARNING: a spherical joint passed its cone limit\n";
    if (s.max_penetration_mm > s.penetration_tolerance_mm) {
      std::cerr << "[sim] WARNING: fragments interpenetrated " << s.max_penetration_mm << " mm (tolerance "
                << s.penetration_tolerance_mm << " mm)\n";
    }
    if (o->json) {
      PrintJson(SimSummaryJson(s));
    } else {
      PrintKeyValues(SimSummaryJson(s));
      std::cout << "actuator_limit_reached: " << (s.actuator_limit_reached ? "yes" : "no") << "\n"
                << "statics (J^-T) relative error: linear " << s.statics_linear_rel_error << ", rotary "
                << s.statics_rotary_rel_error << "\n"
                << "outputs: " << out.target().string() << "\n";
    }
  });
}

}  // namespace robossis::apps
