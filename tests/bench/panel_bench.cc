// Frame time of the control panel on Mesa's software renderer (llvmpipe), at 1920x1080 (the goal: p99 <=
// 33 ms, i.e. 30 frames/s) and, in the same run, with the heavy parts of the 3-D view left out and at 1280x720.
// Needs a display: run it under `xvfb-run -a -s '-screen 0 1920x1080x24'` (see BENCHMARKS.md). Each iteration is
// one whole frame (snapshots, draw, present, glFinish), over the panel's simulated follower running its loops (the
// follower unit at 10 kHz, the leader side at 1 kHz), once with those loops stopped (the panel's cost alone), and once
// with the camera orbiting (every frame a new view).
// Counters: p50_ms, p99_ms (over the iterations), p99_budget = p99 / 33.3 ms, and the p50 of each frame phase
// (apps::FramePhase: update, layout, raster, present); triangles = ImGui's, direct_prims = the lines and triangles
// drawn directly (src/apps/panel/direct_draw.h).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "haptics/haptics_config.h"
#include "haptics/transfer/transfer_config.h"
#include "robot/sim/sim_config.h"
#include "src/apps/panel/panel_window.h"
#include "src/core/config.h"
#include "src/core/rt/clock.h"
#include "src/panel/local_session_backend.h"
#include "src/teleop/teleop_session.h"

namespace {

using namespace robossis;

void PanelFrame(benchmark::State& state, int width, int height, bool bone, bool slice, bool loops = true,
                bool orbit = false) {
  const std::filesystem::path config = DefaultDataDir() / "config";
  const transfer::TransferConfig transfer = transfer::TransferConfig::FromYaml(config / "transfer.yaml");
  const sim::SimConfig sim_config = sim::LoadSimConfig(config / "sim.yaml", DefaultDataDir());
  apps::PanelModels models{robot::RsrModel::FromYaml(config / "rsr.yaml"),
                           robot::Sigma7Model::FromYaml(config / "sigma7.yaml"),
                           panel::PanelConfig::FromYaml(config / "panel.yaml"),
                           {transfer.caps.max_linear_speed_m_s, transfer.caps.max_angular_speed_rad_s},
                           nullptr,
                           haptics::HapticsConfig::FromYaml(config / "haptics.yaml").hardware_default_method,
                           transfer.rates.actuation_rate_hz};
  if (bone) models.fragments = std::make_shared<const sim::BoneFragments>(sim::BuildBoneFragments(sim_config, models.rsr));
  const rt::MonotonicClock clock;
  const teleop::TeleopSetup setup = teleop::TeleopSetup::Load(DefaultDataDir(), models.rsr, models.hc);
  panel::LocalSessionBackend backend(models.rsr, teleop::MakeFollowerBackEnd("sim", setup, 0), setup.follower,
                                     setup.actuation, panel::JogLimits{}, setup.transfer.rates,
                                     clock);
  if (loops) backend.Start();  // without the loops the follower stands still: the panel's own cost alone
  backend.SendCommand(teleop::StateCommand::kHome);
  if (!loops) {  // a status to draw: half a second of follower ticks on this thread, then nothing moves
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(500);
    while (std::chrono::steady_clock::now() < until) backend.Step();
  }
  apps::PanelWindowOptions options;
  options.width_px = width;
  options.height_px = height;
  options.vsync = false;
  options.workspace_slice = slice;
  // A jog in progress, so that the pose, the gauges and the plots change every frame.
  std::string script = "0.3 set jog.axis x\n0.3 set jog.amount 20\n0.3 set jog.duration_s 30\n0.4 click jog.go\n";
  // Orbiting: the camera turns by 0.5 deg every 20 ms, so that every frame draws a new view (nothing the view keeps
  // from the last frame, such as the slice's image, is reused).
  for (int k = 0; orbit && k < 3000; ++k)
    script += std::to_string(0.5 + 0.02 * k) + " set view.azimuth_deg " + std::to_string(30 + 0.5 * k) + "\n";
  options.script = panel::ParseScript(script, "bench");
  apps::PanelWindow window(backend, models, options);
  // Warm-up: the first frames build the font atlas, and the workspace slice arrives after ~0.1-1 s.
  const auto warm_until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (std::chrono::steady_clock::now() < warm_until) window.Frame();
  std::vector<double> ms;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    window.Frame();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  auto at = [&](double q) { return ms.empty() ? 0.0 : ms[std::min(ms.size() - 1, static_cast<std::size_t>(q * (ms.size() - 1) + 0.5))]; };
  state.counters["p50_ms"] = at(0.50);
  state.counters["p99_ms"] = at(0.99);
  state.counters["p99_budget"] = at(0.99) / (1000.0 / 30.0);
  // Where the time went (p50 of each phase over the whole run, warm-up included).
  const apps::PanelRunResult result = window.Result();
  state.counters["update_ms"] = result.phase_p50_ms[static_cast<int>(apps::FramePhase::kUpdate)];
  state.counters["layout_ms"] = result.phase_p50_ms[static_cast<int>(apps::FramePhase::kLayout)];
  state.counters["raster_ms"] = result.phase_p50_ms[static_cast<int>(apps::FramePhase::kRaster)];
  state.counters["present_ms"] = result.phase_p50_ms[static_cast<int>(apps::FramePhase::kPresent)];
  state.counters["triangles"] = static_cast<double>(result.last_frame_triangles);
  state.counters["direct_prims"] = static_cast<double>(result.last_frame_direct_primitives);
  backend.Stop();
}

BENCHMARK_CAPTURE(PanelFrame, full_1920x1080, 1920, 1080, true, true)->Unit(benchmark::kMillisecond)->Iterations(300);
BENCHMARK_CAPTURE(PanelFrame, no_bone_no_slice_1920x1080, 1920, 1080, false, false)
    ->Unit(benchmark::kMillisecond)->Iterations(300);
BENCHMARK_CAPTURE(PanelFrame, full_1280x720, 1280, 720, true, true)->Unit(benchmark::kMillisecond)->Iterations(300);
BENCHMARK_CAPTURE(PanelFrame, full_1920x1080_loops_stopped, 1920, 1080, true, true, false)
    ->Unit(benchmark::kMillisecond)->Iterations(300);
BENCHMARK_CAPTURE(PanelFrame, full_1920x1080_orbiting, 1920, 1080, true, true, true, true)
    ->Unit(benchmark::kMillisecond)->Iterations(300);

}  // namespace
