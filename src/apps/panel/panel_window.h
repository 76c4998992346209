#pragma once
// The control panel's window (paper Fig. 13): Dear ImGui on GLFW and OpenGL 3, drawing a PanelController over any
// PanelBackend. `robossis panel` runs it over the panel's own in-process session (the follower unit over the Bullet
// RSR and, in haptic mode, the leader unit with the simulated sigma.7: panel::LocalSessionBackend). The window
// thread only reads snapshots and queues commands: it never blocks a real-time loop.

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "robot/rsr_model.h"
#include "robot/sigma7_model.h"
#include "robot/sim/bone_fragments.h"
#include "src/panel/haptic_mode.h"
#include "src/panel/panel_backend.h"
#include "src/panel/panel_config.h"
#include "src/core/files.h"
#include "src/panel/script.h"

namespace robossis::apps {

struct PanelWindowOptions {
  int width_px = 1600;
  int height_px = 900;
  std::vector<panel::ScriptAction> script;  // played against the panel's clock (s since the window opened)
  std::string screenshot_path;              // PNG of the last frame ("" for none)
  long max_frames = 0;                      // exit after this many frames (0: until closed or the script quits)
  bool vsync = true;                        // off for the frame-time benchmark
  bool workspace_slice = true;              // the live dexterous slice around the ring
  OutputPolicy output;                      // how screenshots are written (--force, the inputs they must spare)
};

// Where a frame's time goes: the script and the snapshots (and the slice poll), the ImGui layout with the 3-D
// view's draw lists, the rasterisation (draw calls and glFinish), the present (screenshots, swap, glFinish).
enum class FramePhase { kUpdate, kLayout, kRaster, kPresent };
inline constexpr int kFramePhases = 4;

struct PanelRunResult {
  long frames = 0;
  double frame_p50_ms = 0;
  double frame_p99_ms = 0;
  double frame_max_ms = 0;
  std::array<double, kFramePhases> phase_p50_ms{};  // by FramePhase
  long last_frame_triangles = 0;                    // ImGui's draw data of the last frame (the rasteriser's work)
  long last_frame_direct_primitives = 0;            // and the lines and triangles drawn directly (direct_draw.h)
  std::vector<std::string> screenshots;  // written PNGs
  double elapsed_s = 0;
  // The panel's own state at the end, for scripted tests.
  std::string message;          // the last refusal shown to the operator
  std::string last_fault;
  bool haptic_enabled = false;
  bool clutched = false;
  std::string cap_preset;
  std::string rendering_method;
  double max_hand_force_n = 0;  // the largest |force on the hand| the panel showed (the arrows and the force plot)
};

// Everything the window draws that does not come from the backend.
struct PanelModels {
  robot::RsrModel rsr;
  robot::Sigma7Model hc;
  panel::PanelConfig config;
  panel::SpeedCapValues demonstration_caps;
  std::shared_ptr<const sim::BoneFragments> fragments;  // may be null
  std::string default_method;  // haptic mode's rendering method at start (haptics.yaml hardware_default_method)
  double actuation_rate_hz = 0;  // transfer.yaml rates.actuation_rate_hz: the jog preview checks every tick
};

// The window, one frame at a time (the benchmark times Frame()).
class PanelWindow {
 public:
  // Opens the window. Throws std::runtime_error when no window can be opened.
  PanelWindow(panel::PanelBackend& backend, const PanelModels& models, const PanelWindowOptions& options);
  ~PanelWindow();
  PanelWindow(const PanelWindow&) = delete;
  PanelWindow& operator=(const PanelWindow&) = delete;
  // Plays the due script actions, reads the snapshots, draws and presents one frame, writes the due screenshots.
  // False when the panel should close (window closed, script quit, max_frames reached). Throws
  // std::invalid_argument for a script action the panel does not know (naming the script line).
  bool Frame();
  // The frame statistics and the panel's state so far.
  PanelRunResult Result() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct AppContext;  // src/apps/app_context.h

// For `robossis panel` and any other back end's command (src/apps/panel/cmd_panel.cc): the models, panel.yaml,
// the demonstration caps (transfer.yaml) and, with_bone, the femur fragments to draw; and the jog limits, which are
// the follower's own (follower.yaml, caps from transfer.yaml). Throw std::runtime_error naming the file and key.
PanelModels LoadPanelModels(const AppContext& context, bool with_bone);
panel::JogLimits LoadJogLimits(const AppContext& context, const PanelModels& models);

// Opens the window, runs until it is closed, the script quits or max_frames, and returns the frame statistics.
// Throws std::runtime_error when no window can be opened, std::invalid_argument for a script action the panel does
// not know (naming the script line).
PanelRunResult RunPanelWindow(panel::PanelBackend& backend, const PanelModels& models,
                              const PanelWindowOptions& options);

// Writes the current OpenGL framebuffer (width x height) as a PNG through WriteOutputFile (atomic, checked against
// `output`); throws naming `option` and the path.
void SaveFramebufferPng(const OutputPolicy& output, const std::string& option, const std::string& path, int width,
                        int height);

}  // namespace robossis::apps
