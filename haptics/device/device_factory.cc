#include "haptics/device/device_factory.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "haptics/device/dhd_device.h"
#include "haptics/device/simulated_device.h"
#include "haptics/scenarios/scenario.h"
#include "src/core/pose.h"

namespace robossis::haptics {

std::vector<std::string> KnownDevices() { return {"sim", "replay:FILE.csv", "dhd[:KEY=VALUE,...]"}; }

namespace {

HandScript CircleScript(const robot::Sigma7Model& sigma7, const DeviceScriptOptions& o) {
  if (!(o.sim_radius_m >= 0) || !(o.sim_frequency_hz > 0) || !std::isfinite(o.sim_yaw_amplitude_rad)) {
    throw std::invalid_argument("device sim: sim_radius_m must be >= 0, sim_frequency_hz > 0");
  }
  HandScript s;
  s.name = "circle";
  const Eigen::Vector3d c = sigma7.p_center_O();
  const double r = o.sim_radius_m, w = 2 * std::numbers::pi * o.sim_frequency_hz, a = o.sim_yaw_amplitude_rad;
  // A circle through the centre (the hand starts there at rest), yaw swinging at the same frequency.
  s.target = [c, r, w, a](double t) {
    HandTarget h;
    h.X_OH.translation() = c + r * Eigen::Vector3d(std::sin(w * t), 1 - std::cos(w * t), 0);
    h.X_OH.linear() = Eigen::AngleAxisd(a * std::sin(w * t), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    h.v_O = r * w * Eigen::Vector3d(std::cos(w * t), std::sin(w * t), 0);
    h.w_O = Eigen::Vector3d(0, 0, a * w * std::cos(w * t));
    return h;
  };
  return s;
}

HandScript ReplayScript(const std::string& file, const robot::Sigma7Model& sigma7, const HapticsConfig& haptics,
                        const DeviceScriptOptions& o) {
  o.replay_frame.Validate();
  const Scenario recording = LoadTrajectoryCsv(file, haptics.hand);
  const Episode& e = recording.episodes.front();
  // Where the recorded RSR poses put the hand: the recording's first pose at the device centre.
  HcToRsrMap place;
  place.X_OH_anchor.translation() = sigma7.p_center_O();
  place.X_FM_anchor = e.X_FM_start;
  place.frame = o.replay_frame;
  HandScript s;
  s.name = recording.name;
  s.duration_s = e.duration_s;
  s.end_of_script_status = true;
  auto target_FM = e.target_FM;
  const double duration = e.duration_s;
  s.target = [target_FM, place, duration](double t) {
    // Velocities by central differences over 0.1 ms (the recording is piecewise linear between samples).
    const double h = 1e-4;
    const double t0 = std::max(0.0, t - h), t1 = std::min(duration, t + h);
    HandTarget target;
    target.X_OH = place.ToHc(target_FM(t));
    if (t1 > t0) {
      const Eigen::Isometry3d A = place.ToHc(target_FM(t0)), B = place.ToHc(target_FM(t1));
      target.v_O = (B.translation() - A.translation()) / (t1 - t0);
      target.w_O = RotationVector(B.linear() * A.linear().transpose()) / (t1 - t0);
    }
    return target;
  };
  return s;
}

}  // namespace

std::unique_ptr<HapticDevice> MakeDevice(const std::string& spec, const robot::Sigma7Model& sigma7,
                                         const HapticsConfig& haptics, const DeviceLimits& limits,
                                         const DeviceScriptOptions& options) {
  if (spec == "sim") {
    return std::make_unique<SimulatedDevice>(sigma7, haptics.device, haptics.hand, CircleScript(sigma7, options),
                                             limits);
  }
  if (IsDhdDeviceSpec(spec)) return OpenDhdDevice(spec, limits);
  const std::string replay = "replay:";
  if (spec.rfind(replay, 0) == 0 && spec.size() > replay.size()) {
    return std::make_unique<SimulatedDevice>(sigma7, haptics.device, haptics.hand,
                                             ReplayScript(spec.substr(replay.size()), sigma7, haptics, options),
                                             limits);
  }
  std::string known;
  for (const std::string& k : KnownDevices()) known += (known.empty() ? "" : ", ") + k;
  throw std::invalid_argument("--device: unknown device '" + spec + "'; known: " + known);
}

}  // namespace robossis::haptics
