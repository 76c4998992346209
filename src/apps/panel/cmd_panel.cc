// robossis panel: the control panel window over the panel's own session: the follower unit over a follower back end
// (the Bullet RSR unless --follower says otherwise) and, in haptic mode, the leader unit with a haptic device (the
// simulated sigma.7 unless --device says otherwise); or, with --link dds, a remote follower over the two-machine link
// with the panel's credentials.

#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include <CLI/CLI.hpp>

#include "haptics/haptics_config.h"
#include "haptics/transfer/transfer_config.h"
#include "robot/actuation/actuation_config.h"
#include "robot/sim/sim_config.h"
#include "src/apps/app_context.h"
#include "src/apps/link_cli.h"
#include "src/apps/panel/panel_window.h"
#include "src/core/rt/clock.h"
#include "src/core/units.h"
#include "src/panel/dds_follower_backend.h"
#include "src/panel/local_session_backend.h"
#include "src/panel/view_model.h"
#include "src/teleop/follower_config.h"
#include "src/teleop/teleop_session.h"

namespace robossis::apps {

PanelModels LoadPanelModels(const AppContext& context, bool with_bone) {
  const transfer::TransferConfig transfer = transfer::TransferConfig::FromYaml(context.ConfigPath("transfer.yaml"));
  PanelModels models{context.LoadRsr(), context.LoadSigma7(),
                     panel::PanelConfig::FromYaml(context.ConfigPath("panel.yaml")),
                     {transfer.caps.max_linear_speed_m_s, transfer.caps.max_angular_speed_rad_s},
                     nullptr,
                     haptics::HapticsConfig::FromYaml(context.ConfigPath("haptics.yaml")).hardware_default_method,
                     transfer.rates.actuation_rate_hz};
  if (with_bone) {
    const sim::SimConfig sim_config = sim::LoadSimConfig(context.ConfigPath("sim.yaml"), context.data_dir);
    models.fragments = std::make_shared<const sim::BoneFragments>(sim::BuildBoneFragments(sim_config, models.rsr));
  }
  return models;
}

panel::JogLimits LoadJogLimits(const AppContext& context, const PanelModels& models) {
  transfer::SpeedCaps caps;
  caps.max_linear_speed_m_s = models.demonstration_caps.max_linear_speed_m_s;
  caps.max_angular_speed_rad_s = models.demonstration_caps.max_angular_speed_rad_s;
  panel::JogLimits limits;
  limits.setpoint = teleop::FollowerConfig::FromYaml(context.ConfigPath("follower.yaml"), caps).setpoint;
  limits.actuation_rate_hz = models.actuation_rate_hz;
  return limits;
}

void RegisterPanelCommand(CLI::App& app, const AppContext& context) {
  struct Options {
    std::string script;
    std::string screenshot;
    long frames = 0;
    int width = 0, height = 0;
    bool no_vsync = false;
    bool no_bone = false;
    bool no_slice = false;
    bool json = false;
    std::string device = "sim";
    std::string follower = "sim";
    std::string link_kind = "sim";
    link::LinkOptions link_options;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "panel",
      "The control panel (Fig. 13): jog (eq. 9), haptic mode, E-stop, 3-D view, gauges; over its own follower unit "
      "(simulated, or the robot's HAL drives) or a remote one over DDS.\n"
      "Example: xvfb-run -a robossis panel --script jog.txt --screenshot panel.png --json");
  // No CLI11 file check: LoadScript refuses a missing or non-regular file in the project's words.
  cmd->add_option("--script", options->script, "Timed UI actions to play (see src/panel/script.h)");
  cmd->add_option("--screenshot", options->screenshot, "Save the last frame as this PNG");
  cmd->add_option("--frames", options->frames, "Exit after N frames")->check(CLI::NonNegativeNumber);
  cmd->add_option("--width", options->width, "Window width in pixels (default: panel.yaml)")->check(CLI::PositiveNumber);
  cmd->add_option("--height", options->height, "Window height in pixels (default: panel.yaml)")->check(CLI::PositiveNumber);
  cmd->add_flag("--no-vsync", options->no_vsync, "Render as fast as possible (frame-time measurements)");
  cmd->add_flag("--no-bone", options->no_bone, "Do not load and draw the femur fragments");
  cmd->add_flag("--no-slice", options->no_slice, "Do not draw the live workspace slice");
  cmd->add_option("--device", options->device,
                  "Haptic device of haptic mode: sim (the simulated sigma.7, default), replay:FILE.csv, dhd[:...]");
  CLI::Option* follower = cmd->add_option("--follower", options->follower,
                  "Follower back end of the panel's own session: sim (the Bullet RSR, default) or hal (the robot's "
                  "LinuxCNC HAL drives on this machine, hal.yaml; halrun must be running the HAL file)")
      ->check(CLI::IsMember({"sim", "hal"}));
  cmd->add_option("--link", options->link_kind,
                  "sim: the panel's own in-process session (default); dds: a remote follower over the link, with the "
                  "panel's credentials (state commands only)")
      ->check(CLI::IsMember({"sim", "dds"}));
  AddLinkOptions(*cmd, options->link_options);
  cmd->add_flag("--json", options->json, "Print the final follower status and the frame times as JSON");
  cmd->callback([options, follower, &context] {
    const OutputPolicy output = context.Output({{"--script", options->script}});
    if (!options->screenshot.empty()) output.CheckFile("--screenshot", options->screenshot);
    const PanelModels models = LoadPanelModels(context, !options->no_bone);
    PanelWindowOptions window;
    window.width_px = options->width > 0 ? options->width : models.config.window_width_px;
    window.height_px = options->height > 0 ? options->height : models.config.window_height_px;
    if (!options->script.empty()) window.script = panel::LoadScript(options->script);
    window.screenshot_path = options->screenshot;
    window.output = output;
    window.max_frames = options->frames;
    window.vsync = !options->no_vsync;
    window.workspace_slice = !options->no_slice;

    // The follower unit's and the leader unit's configs as `robossis teleop` loads them; the follower's caps are
    // the jog limits' (LoadJogLimits): the demonstration caps of transfer.yaml.
    const teleop::TeleopSetup setup = teleop::TeleopSetup::Load(context.data_dir, models.rsr, models.hc);
    const panel::JogLimits limits = LoadJogLimits(context, models);
    const rt::MonotonicClock clock;
    std::unique_ptr<panel::PanelBackend> backend;
    if (options->link_kind == "dds") {
      if (follower->count() > 0)
        throw std::invalid_argument("--follower: only for the panel's own session (--link sim); a remote follower "
                                    "(--link dds) runs its own back end");
      CheckLinkOptions(options->link_options, std::cerr);
      options->link_options.tuning = link::LinkTuning::FromYaml(context.ConfigPath("link.yaml"));
      backend = std::make_unique<panel::DdsFollowerBackend>(options->link_options);
    } else {
      auto local = std::make_unique<panel::LocalSessionBackend>(
          models.rsr, teleop::MakeFollowerBackEnd(options->follower, setup, 0), setup.follower, setup.actuation,
          limits, setup.transfer.rates, clock);
      try {
        local->AttachHapticLeader({&models.hc, setup.haptics, setup.transfer, setup.leader, options->device,
                                   nullptr});
      } catch (const std::exception& e) {
        throw std::runtime_error(std::string("--device: ") + e.what());
      }
      for (const std::string& warning : local->Start()) std::cerr << "robossis: warning: " << warning << "\n";
      backend = std::move(local);
    }
    const PanelRunResult result = RunPanelWindow(*backend, models, window);
    if (auto* local = dynamic_cast<panel::LocalSessionBackend*>(backend.get())) local->Stop();
    if (!options->json) return;
    teleop::FollowerStatusMessage status;
    backend->ReadStatus(status);
    panel::LoopHealth health;
    backend->ReadHealth(health);
    const panel::PanelViewModel view = panel::BuildViewModel(models.rsr, status);
    nlohmann::ordered_json out;
    out["frames"] = result.frames;
    out["elapsed_s"] = result.elapsed_s;
    out["frame_ms"] = {{"p50", result.frame_p50_ms}, {"p99", result.frame_p99_ms}, {"max", result.frame_max_ms}};
    out["window_px"] = {window.width_px, window.height_px};
    out["screenshots"] = result.screenshots;
    out["message"] = result.message;
    out["last_fault"] = result.last_fault;
    out["haptic"] = {{"enabled", result.haptic_enabled}, {"clutched", result.clutched},
                     {"caps", result.cap_preset}, {"method", result.rendering_method},
                     {"max_hand_force_n", result.max_hand_force_n}, {"device", options->device}};
    out["link"] = options->link_kind;
    out["follower"] = options->link_kind == "dds" ? "remote" : options->follower;
    out["state"] = view.state_name;
    out["fault_reason"] = teleop::ToString(status.fault_reason);
    out["pose_mm_deg"] = view.pose_mm_deg;
    out["setpoints_accepted"] = status.setpoints_accepted;
    out["setpoints_rejected"] = status.setpoints_rejected;
    out["loop"] = {{"ticks", health.ticks},
                   {"overruns", health.follower_loop.overruns},
                   {"overruns_late_wake", health.follower_loop.overruns_late_wake},
                   {"overruns_long_tick", health.follower_loop.overruns_long_tick},
                   {"leader_overruns", health.leader_loop.overruns},
                   {"leader_overruns_late_wake", health.leader_loop.overruns_late_wake},
                   {"leader_overruns_long_tick", health.leader_loop.overruns_long_tick},
                   {"max_jitter_ms", 1e3 * health.max_jitter_s}};
    PrintJson(out);
  });
}

}  // namespace robossis::apps
