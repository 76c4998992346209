#pragma once
// Haptic device back ends by name, as `robossis teleop --device` and the demo select them:
//
//   sim               the simulated sigma.7, the hand tracing a scripted loop around the device centre (a circle in
//                     the horizontal plane with a yaw swing; size and speed in DeviceScriptOptions), presence held
//   replay:FILE.csv   the simulated sigma.7, the hand following a recorded trajectory (the render-compare replay
//                     format t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg: the RSR pose the hand commands, frame F),
//                     presence held until the recording ends, then kEndOfScript
//
//   dhd[:KEY=VALUE,...]  a real sigma.7 through the Force Dimension SDK, loaded at run time (haptics/device/dhd_device.h,
//                     haptics/device/README.md: lib=, drd=, serial=, index=, hold=, window_ms=)

#include <memory>
#include <string>
#include <vector>

#include "haptics/device/haptic_device.h"
#include "haptics/haptics_config.h"
#include "haptics/transfer/hc_to_rsr_frame.h"
#include "robot/sigma7_model.h"

namespace robossis::haptics {

// The `sim` script (all [assumed], in data/config/leader.yaml): a hand moving steadily through the workspace.
struct DeviceScriptOptions {
  double sim_radius_m = 0.03;
  double sim_frequency_hz = 0.25;
  double sim_yaw_amplitude_rad = 0.35;
  // replay: the recording's first pose is where the device centre maps to (the RSR pose at the clutch), through
  // the hand-to-robot frame map the session uses (transfer.yaml `mapping`), so that the path replayed in F is the
  // path recorded, whatever R_FO and the scales.
  transfer::HcToRsrFrame replay_frame;
};

std::vector<std::string> KnownDevices();  // "sim", "replay:FILE.csv", "dhd[:KEY=VALUE,...]"

// Throws std::invalid_argument for an unknown spec (listing the known ones), std::runtime_error for a bad file.
// `sigma7` must outlive the device.
std::unique_ptr<HapticDevice> MakeDevice(const std::string& spec, const robot::Sigma7Model& sigma7,
                                         const HapticsConfig& haptics, const DeviceLimits& limits,
                                         const DeviceScriptOptions& options);

}  // namespace robossis::haptics
